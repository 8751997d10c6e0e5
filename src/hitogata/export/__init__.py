"""File export: skinned GLB, plain mesh files (OBJ, PLY, GLB), atomic writes."""

from hitogata.export.gltf import GlbSkin, read_glb_skin, write_glb
from hitogata.export.meshfiles import MESH_SUFFIXES, write_mesh

__all__ = ["GlbSkin", "MESH_SUFFIXES", "read_glb_skin", "write_glb", "write_mesh"]
