"""File export: skinned GLB, plain mesh files (OBJ, PLY, GLB), atomic writes.

The names below are imported on first use (`hitogata.lazy`): writing a file
atomically does not load the glTF library.
"""

from typing import TYPE_CHECKING

from hitogata.lazy import lazy_names

if TYPE_CHECKING:
    from hitogata.export.glb_read import GlbSkin, read_glb_skin
    from hitogata.export.gltf import write_glb
    from hitogata.export.meshfiles import MESH_SUFFIXES, write_mesh

__all__ = ["GlbSkin", "MESH_SUFFIXES", "read_glb_skin", "write_glb", "write_mesh"]
__getattr__, __dir__ = lazy_names(globals(), {
    "GlbSkin": "hitogata.export.glb_read",
    "read_glb_skin": "hitogata.export.glb_read",
    "write_glb": "hitogata.export.gltf",
    "MESH_SUFFIXES": "hitogata.export.meshfiles",
    "write_mesh": "hitogata.export.meshfiles",
})
