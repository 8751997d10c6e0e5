"""Argument types shared by the sub-commands (argparse turns their errors into one line)."""

from __future__ import annotations

import argparse
from pathlib import Path

from hitogata.errors import HitogataError

# option → (attribute, default): the body options, their defaults owned here once
BODY_DEFAULTS = {
    "--sex": ("sex", "female"),
    "--age": ("age", 30.0),
    "--stature": ("stature", None),  # None: the default body's of that sex (`hitogata.body.default_measurements`)
    "--mass": ("mass", None),
    "--muscle-tone": ("muscle_tone", None),
    "--proportions": ("proportions", 0.5),
}


def years(text: str) -> float:
    """An age in years."""
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"age {text!r}: allowed a number of years, 1–90") from None


def unit_fraction(text: str) -> float:
    """A number 0..1 (checked by the library, which names the parameter)."""
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: allowed a number 0..1") from None


def add_body_arguments(parser: argparse.ArgumentParser) -> None:
    """--sex --age --stature --mass --muscle-tone --proportions, as a person writes them."""
    d = {option: default for option, (_, default) in BODY_DEFAULTS.items()}
    parser.add_argument("--sex", default=d["--sex"], help="female, male, or 0 (female) … 1 (male); default female")
    parser.add_argument("--age", type=years, default=d["--age"], help="years, 1–90 (below 18: stature and mass default to the growth references' medians); default 30")
    parser.add_argument("--stature", default=d["--stature"],
                        help="e.g. 165cm, 1.65m; default the default body's: female 165cm, male 178cm; below 18 the growth references' median")
    parser.add_argument("--mass", default=d["--mass"], help="e.g. 58kg; default the default body's: female 62kg, male 78kg; below 18 the growth references' median")
    parser.add_argument("--muscle-tone", type=unit_fraction, default=d["--muscle-tone"],
                        help="0..1, 0.5 = average; default: follows the mass (MakeHuman's build path)")
    parser.add_argument("--proportions", type=unit_fraction, default=d["--proportions"],
                        help="0..1, 0.5 = average")


def body_options_given(args: argparse.Namespace) -> list[str]:
    """The body options given a value other than their default."""
    return [option for option, (name, default) in BODY_DEFAULTS.items() if getattr(args, name) != default]


def refuse_body_options(args: argparse.Namespace, why: str) -> None:
    """A one-line error if a body option was given where it does not apply (it would be silently ignored)."""
    given = body_options_given(args)
    if given:
        value = getattr(args, BODY_DEFAULTS[given[0]][0])
        raise HitogataError(f"{given[0]} {value}: does not apply here ({why}); leave out {', '.join(given)}")


def add_materials_argument(parser: argparse.ArgumentParser, help: str = "the tissue materials",
                           option: str = "--materials", default_text: str | None = None) -> None:
    """--materials (or `option`): a shipped preset by name or a materials TOML file (e.g. written by
    `hitogata identify`)."""
    from hitogata.commands.paths import input_path
    from hitogata.options import DEFAULT_MATERIALS, MATERIALS_PRESETS

    def presets() -> dict[str, Path]:  # imported when an argument is checked: the materials module is slow to load
        from hitogata.elastic.materials import shipped_materials

        return shipped_materials()

    parser.add_argument(option, default=None, type=input_path("file", suffixes=(".toml",), names=presets),
                        help=f"{help}: a preset ({', '.join(MATERIALS_PRESETS)}) or a materials TOML file (e.g. "
                             f"from hitogata identify); default {default_text or DEFAULT_MATERIALS}")


def add_cache_argument(parser: argparse.ArgumentParser) -> None:
    """--no-cache, on a command that builds an elastic model (`hitogata.disk_cache`; `cli.main` applies it)."""
    parser.add_argument("--no-cache", action="store_true",
                        help="build the elastic model afresh, neither reading nor writing the model cache "
                             "(as HITOGATA_NO_CACHE=1)")
