"""The viewer app on a real viser server, driven through its actions (the browser test drives the page)."""

import re
import signal
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request

import numpy as np
import pytest

pytest.importorskip("viser", reason="the viewer needs viser (pip install viser)")

from hitogata.errors import HitogataError  # noqa: E402
from hitogata.viewer import serve  # noqa: E402
from hitogata.garment.fabric import Fabric  # noqa: E402
from hitogata.garment.pressure import Garment  # noqa: E402
from hitogata.viewer.colouring import SKIN_RGB  # noqa: E402
from hitogata.viewer.player import RESULT_FILE  # noqa: E402
from hitogata.viewer.origin import refusal  # noqa: E402
from waiting import PATIENCE, wait_for  # noqa: E402
from websockets.exceptions import InvalidStatus  # noqa: E402
from websockets.sync.client import connect  # noqa: E402


@pytest.fixture(scope="module")
def app(female):
    viewer = serve(female, port=0)
    yield viewer
    viewer.stop()


@pytest.fixture(autouse=True)
def rest_pose(app):
    app.back_to_muscles()
    app.reset_pose()
    yield


def test_serves_on_loopback_by_default(app):
    assert app.url.startswith("http://127.0.0.1:")
    with socket.create_connection(("127.0.0.1", app.server.get_port()), timeout=5):
        pass


def test_an_address_this_machine_cannot_listen_on_is_a_one_line_error(female):
    with pytest.raises(HitogataError, match=r"host '999\.1\.1\.1': cannot listen there"):
        serve(female, host="999.1.1.1", port=0)


def test_a_muscle_move_poses_the_skin_and_echoes_the_antagonist(app, female):
    app.move_muscle("biceps_brachii_r", 20.0)
    assert app.state.posed.angle("forearm_r.flexion") > 0.3
    np.testing.assert_allclose(app.scene.skin.vertices, app.state.posed.vertices.astype(np.float32))
    assert app.panels.sliders["triceps_brachii_r"].value < -1.0
    assert app.panels.sliders["biceps_brachii_r"].value == 0.0  # the moved one is the person's to set
    bones = app.scene.skeleton.points
    assert bones.shape == (65, 2, 3) and not np.allclose(bones[:, 0], app.state.poser.skeleton.joints)


def test_measurements_follow_the_pose(app):
    assert app.wait_idle(PATIENCE)
    rest = app.panels.measurements.content
    app.move_muscle("rectus_abdominis_l", 40.0)
    assert app.wait_idle(PATIENCE)
    bent = app.panels.measurements.content
    assert bent != rest and "stature" in bent and "waist girth" in bent
    stature = float(re.search(r"\| stature \| ([\d.]+) \|", bent).group(1))
    assert stature < 160.0  # bent forward


def test_bad_stature_is_a_message_and_the_server_keeps_running(app):
    app.rebuild_body("female", 30.0, 250.0, 60.0)
    assert app.panels.message.content.startswith("**Error:** stature 250.0 cm: allowed 140")
    app.rebuild_body("female", 30.0, None, 60.0)
    assert "stature None: allowed a number" in app.panels.message.content
    assert app.panels.rebuild.disabled is False
    app.move_muscle("deltoid_l", 10.0)  # still posing
    assert app.state.drivers == {"deltoid_l": 0.1}


def test_broken_scenario_file_is_a_message(app, tmp_path):
    broken = tmp_path / "broken.toml"
    broken.write_text("[[keyframe]]\ntime = 'soon'\n[[keyframe]]\ntime = 1.0\n")
    app.load_sequence(str(broken))
    assert "**Error:**" in app.panels.message.content and "broken.toml" in app.panels.message.content
    app.load_sequence("")
    assert "sequence path: empty" in app.panels.message.content


def test_player_loads_plays_scrubs_and_returns_to_muscles(app, tmp_path):
    poser = app.state.poser
    q = np.zeros((10, poser.skeleton.n_dofs))
    q[:, poser.skeleton.dof_index("shank_l.flexion")] = np.linspace(0.0, 1.2, 10)
    np.savez(tmp_path / RESULT_FILE, times=np.linspace(0.0, 0.3, 10), vertices=poser.pose_many(q), angles=q)
    app.load_sequence(str(tmp_path))
    assert app.showing_sequence and "10 frames" in app.panels.sequence_info.content
    assert app.panels.time.disabled is False and app.panels.time.max == pytest.approx(0.3)
    app.play()
    assert app.wait_playback(timeout=PATIENCE) and not app.clock.playing
    assert app.clock.time == pytest.approx(0.3)
    np.testing.assert_allclose(app.scene.skin.vertices, poser.pose_many(q[-1:])[0], atol=1e-5)
    app.scrub(0.0)
    np.testing.assert_allclose(app.scene.skin.vertices, poser.body.vertices, atol=1e-5)
    app.move_muscle("hamstrings_r", 10.0)  # a slider takes the body back from the sequence
    assert not app.showing_sequence
    np.testing.assert_allclose(app.scene.skin.vertices, app.state.posed.vertices, atol=1e-5)


def test_strain_and_tissue_layers(app):
    app.move_muscle("iliopsoas_r", 30.0)
    app.set_layer("strain", True)
    assert app.wait_idle(PATIENCE) and app.scene.strain is not None and app.scene.strain.visible
    assert not app.scene.skin.visible
    app.set_layer("strain", False)
    assert app.scene.skin.visible and not app.scene.strain.visible
    app.set_layer("tissue", True)
    assert wait_for(lambda: "tissue regions ready" in app.panels.message.content)
    regions = [surface.region for surface, _ in app.scene.tissue]
    assert regions == ["bone", "viscera", "muscle"]  # bone: the held capsules' surface
    surface, handle = app.scene.tissue[0]
    np.testing.assert_allclose(handle.vertices, surface.posed(app.state.posed.pose), atol=1e-5)
    app.set_layer("tissue", False)
    assert not any(h.visible for _, h in app.scene.tissue)


def test_the_colour_map_choice_is_shown_and_a_missing_garment_is_a_message(app):
    assert app.panels.colour_map.options == ("skin strain", "zone stretch")
    app.move_muscle("iliopsoas_r", 30.0)
    app.set_colour_map("zone stretch")
    assert app.wait_idle(PATIENCE) and app.scene.strain.visible and app.panels.colours.value
    frame = app.frame
    np.testing.assert_array_equal(app.scene.strain_colours,
                                  app.colouring.colours("zone stretch", frame.vertices, frame.rig_joints))
    outside = ~app.colouring.in_zones()
    assert (app.scene.strain_colours[outside] == SKIN_RGB).all() and "fit report's scale" in app.panels.legend.content
    app.set_colour_map("pressure")
    assert app.panels.message.content.startswith("**Error:** colour map 'pressure' (pressure needs a garment")
    assert app.colour_map == "zone stretch"
    app.set_colour_map("skin strain")
    app.set_layer("strain", False)


@pytest.fixture(scope="module")
def dressed(female):
    """A viewer with a stretch garment: 15 % smaller round than the standing body, 400 N/m."""
    viewer = serve(female, port=0, garment=(Garment(ease=-0.15), Fabric.linear(400.0)))
    yield viewer
    viewer.stop()


def test_the_pressure_map_follows_the_played_motion(dressed, tmp_path):
    """Played to its end (a knee bending to 70°), the colours are the last frame's pressure; scrubbed back, the
    rest's. The map is state: what `SkinColours` gives for the shown frame (no timing is asserted)."""
    app = dressed
    assert app.panels.colour_map.options == ("skin strain", "zone stretch", "pressure")
    poser = app.state.poser
    q = np.zeros((6, poser.skeleton.n_dofs))
    q[:, poser.skeleton.dof_index("shank_r.flexion")] = np.linspace(0.0, 1.2, 6)
    np.savez(tmp_path / RESULT_FILE, times=np.linspace(0.0, 0.2, 6), vertices=poser.pose_many(q), angles=q)
    app.load_sequence(str(tmp_path))
    app.set_colour_map("pressure")
    assert "mmHg" in app.panels.legend.content
    app.play()
    assert app.wait_playback(timeout=PATIENCE) and app.wait_idle(PATIENCE)
    last = app.frame
    bent = app.colouring.values("pressure", last.vertices, last.rig_joints)
    np.testing.assert_array_equal(app.scene.strain_colours,
                                  app.colouring.colours("pressure", last.vertices, last.rig_joints))
    app.scrub(0.0)
    assert app.wait_idle(PATIENCE)
    rest = app.colouring.values("pressure", app.frame.vertices, app.frame.rig_joints)
    np.testing.assert_array_equal(app.scene.strain_colours,
                                  app.colouring.colours("pressure", app.frame.vertices, app.frame.rig_joints))
    knee = np.isfinite(bent) & np.isfinite(rest)
    assert (round(np.nanmax(bent), 1), round(np.nanmax(rest), 1), int(knee.sum())) == (32.0, 25.4, 993)  # mmHg
    assert np.isnan(rest).sum() > len(rest) // 2  # the stocking covers the right leg only


def test_snapshot_html_is_self_contained(app):
    from hitogata.viewer.export import snapshot_html

    html = snapshot_html(app.server)
    assert html.lstrip().lower().startswith("<!doctype html")
    assert not re.findall(r'(?:src|href)="https?://', html)


def test_rebuilt_body_keeps_the_pose(app):
    app.move_muscle("biceps_brachii_l", 15.0)
    angles = app.state.posed.angles.copy()
    app.rebuild_body("male", 40.0, 180.0, 80.0)
    assert "body rebuilt" in app.panels.message.content
    assert app.state.body.stature == pytest.approx(1.80, abs=1e-3)
    np.testing.assert_allclose(app.state.posed.angles, angles, atol=1e-9)
    k = app.state.muscles.index("biceps_brachii_l")
    assert app.panels.sliders["biceps_brachii_l"].max == pytest.approx(app.state.ranges.high[k])


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_the_command_prints_its_url_and_rejects_a_bad_port():
    bad = subprocess.run([sys.executable, "-m", "hitogata.cli", "view", "--port", "http"], capture_output=True, text=True)
    assert bad.returncode == 2 and "port 'http': allowed a whole number 1–65535" in bad.stderr
    port = free_port()
    proc = subprocess.Popen([sys.executable, "-m", "hitogata.cli", "view", "--port", str(port)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = ""
        end = time.monotonic() + PATIENCE
        while "hitogata viewer:" not in line and time.monotonic() < end:
            line = proc.stdout.readline()
        assert f"hitogata viewer: http://127.0.0.1:{port}" in line
        proc.send_signal(signal.SIGINT)  # Ctrl-C: stopped as every command is, exit 130
        _, err = proc.communicate(timeout=PATIENCE)
    finally:
        proc.kill()
    assert proc.returncode == 130 and err.strip() == "hitogata: interrupted; nothing written", err


def test_the_skeleton_layer_stays_under_the_skin(app):
    """Every drawn line is under the skin by half its thickness, at rest and bent (`bone_reach`)."""
    from hitogata.made_to_measure.scan_fit.closest import signed_distances
    from hitogata.viewer.scene import BONE_LINE_THICKNESS

    s = np.linspace(0.0, 1.0, 11)
    for muscle, percent in ((None, 0.0), ("rectus_abdominis_l", 40.0), ("biceps_brachii_r", 20.0)):
        if muscle is not None:
            app.move_muscle(muscle, percent)
        bones = np.asarray(app.scene.skeleton.points, dtype=np.float64)
        points = bones[:, 0, None] + s[None, :, None] * (bones[:, 1] - bones[:, 0])[:, None]
        depth = -signed_distances(app.state.posed.vertices, app.state.body.faces, points.reshape(-1, 3))
        assert depth.min() >= BONE_LINE_THICKNESS / 2


def test_the_parts_ending_on_the_skin_are_drawn_short(female):
    """Whole, the crown's and three fingertips' parts on each hand end outside the skin; `bone_reach`
    shortens those and the chin's, the thumbs' and little fingers' (their ends within 2 mm of it)."""
    from hitogata.made_to_measure.scan_fit.closest import signed_distances
    from hitogata.posing import Poser
    from hitogata.viewer.frame import bone_reach

    skeleton = Poser.from_body(female).skeleton
    outside = signed_distances(female.vertices, female.faces, skeleton.tails) > 0
    assert sorted(np.array(skeleton.names)[outside]) == [
        "head", "index_distal_l", "index_distal_r", "middle_distal_l", "middle_distal_r", "ring_distal_l",
        "ring_distal_r"]
    reach = bone_reach(skeleton, female.vertices, female.faces, clearance=0.002)
    shortened = {name: round(float(r), 3) for name, r in zip(skeleton.names, reach) if r < 1.0}
    assert shortened == {
        "head": 0.95, "jaw": 0.95, "thumb_phalanges_l": 0.975, "thumb_phalanges_r": 0.975,
        **{f"{finger}_distal_{side}": 0.925 for finger in ("index", "middle", "ring") for side in "lr"},
        "little_distal_l": 0.725, "little_distal_r": 0.725}


# Only the viewer's own page may connect: another origin (a site the user visits) is refused with 403.

def websocket_status(url: str, origin: str | None) -> int:
    """101 when the handshake succeeds, else the HTTP status of the refusal."""
    try:
        with connect(url.replace("http://", "ws://"), origin=origin, open_timeout=60,
                     additional_headers={}) as ws:
            ws.close()
            return 101
    except InvalidStatus as refused:
        return refused.response.status_code


def test_a_websocket_from_another_page_is_refused(app):
    port = app.server.get_port()
    assert websocket_status(app.url, f"http://evil.example:{port}") == 403
    assert websocket_status(app.url, "http://evil.example") == 403
    assert websocket_status(app.url, "null") == 403  # a sandboxed page or a file
    assert websocket_status(app.url, f"http://127.0.0.1:{port + 1}") == 403  # another local port is another page


def test_the_viewers_own_page_and_a_program_may_connect(app):
    port = app.server.get_port()
    assert websocket_status(app.url, f"http://127.0.0.1:{port}") == 101
    assert websocket_status(app.url, None) == 101


def test_a_foreign_host_name_is_refused_on_a_local_viewer(app):
    """DNS rebinding: evil.example resolving to 127.0.0.1 sends Host: evil.example; the page is not served."""
    request = urllib.request.Request(app.url, headers={"Host": "evil.example"})
    with pytest.raises(urllib.error.HTTPError) as refused:
        urllib.request.urlopen(request, timeout=60)
    assert refused.value.code == 403
    with urllib.request.urlopen(app.url, timeout=60) as page:
        assert page.status == 200


@pytest.mark.parametrize("origin, host, local, refused", [
    (None, "127.0.0.1:8080", True, False),
    ("http://127.0.0.1:8080", "127.0.0.1:8080", True, False),
    ("http://localhost:8080", "localhost:8080", True, False),
    ("http://[::1]:8080", "[::1]:8080", True, False),
    ("http://LOCALHOST:8080", "localhost:8080", True, False),
    ("http://localhost:8080", "127.0.0.1:8080", True, True),
    ("https://evil.example", "127.0.0.1:8080", True, True),
    ("http://evil.example:8080", "evil.example:8080", True, True),
    ("http://studio:8080", "studio:8080", False, False),  # --host 0.0.0.0, reached by the machine's name
    ("http://evil.example", "studio:8080", False, True),
    (None, None, True, True),
])
def test_the_origin_rule(origin, host, local, refused):
    assert (refusal(origin, host, local) is not None) == refused
