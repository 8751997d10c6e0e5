"""Make sure offscreen OpenGL will work before VTK is asked to render.

VTK renders without a display through Mesa's EGL (`vtkEGLRenderWindow`,
selected here through `VTK_DEFAULT_OPENGL_WINDOW` unless the user chose
another window class). When EGL, Mesa's EGL driver or its software renderer
is missing, VTK crashes the whole process (segmentation fault) instead of
raising. So we first load libEGL with ctypes and open a surfaceless Mesa
display, and turn a failure into a one-line `HitogataError` that says which
packages to install. With `vtkOSOpenGLRenderWindow` we check for libOSMesa.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools
import os

from hitogata.errors import HitogataError

WINDOW_VARIABLE = "VTK_DEFAULT_OPENGL_WINDOW"
EGL_WINDOW = "vtkEGLRenderWindow"
OSMESA_WINDOW = "vtkOSOpenGLRenderWindow"
EGL_PACKAGES = "apt-get install -y libegl1 libegl-mesa0 libgl1-mesa-dri"
OSMESA_PACKAGES = "apt-get install -y libosmesa6"
EGL_PLATFORM_SURFACELESS_MESA = 0x31DD


def _egl_works() -> str | None:
    """None if an EGL display initialises, else what is wrong (Mesa's own warnings kept quiet)."""
    quiet = "EGL_LOG_LEVEL" not in os.environ
    if quiet:
        os.environ["EGL_LOG_LEVEL"] = "fatal"
    try:
        return _egl_problem()
    finally:
        if quiet:
            del os.environ["EGL_LOG_LEVEL"]


def _egl_problem() -> str | None:
    if ctypes.util.find_library("EGL") is None:
        return "the EGL library (libEGL.so.1) was not found"
    try:
        egl = ctypes.CDLL("libEGL.so.1")
    except OSError as err:
        return f"libEGL.so.1 cannot be loaded ({err})"
    egl.eglGetDisplay.restype = ctypes.c_void_p
    egl.eglGetDisplay.argtypes = [ctypes.c_void_p]
    egl.eglInitialize.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_int)]
    egl.eglTerminate.argtypes = [ctypes.c_void_p]
    if hasattr(egl, "eglGetPlatformDisplay"):  # EGL 1.5: a display that needs no X server
        egl.eglGetPlatformDisplay.restype = ctypes.c_void_p
        egl.eglGetPlatformDisplay.argtypes = [ctypes.c_uint, ctypes.c_void_p, ctypes.c_void_p]
        display = egl.eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, None, None)
    else:
        display = egl.eglGetDisplay(None)
    if not display:
        return "EGL found no display: Mesa's EGL driver (libEGL_mesa.so.0) seems missing"
    major, minor = ctypes.c_int(), ctypes.c_int()
    if not egl.eglInitialize(display, ctypes.byref(major), ctypes.byref(minor)):
        return "EGL could not start Mesa's software renderer (swrast_dri.so missing?)"
    egl.eglTerminate(display)
    return None


@functools.cache
def _checked(window: str) -> None:
    if window == EGL_WINDOW:
        problem, fix = _egl_works(), EGL_PACKAGES
    elif window == OSMESA_WINDOW:
        problem, fix = (None if ctypes.util.find_library("OSMesa") else "libOSMesa was not found"), OSMESA_PACKAGES
    else:
        return  # a window class the user chose: trust it
    if problem:
        raise HitogataError(f"offscreen rendering ({WINDOW_VARIABLE}={window}): {problem}; install with: {fix}")


def ensure_offscreen_gl() -> str:
    """Select VTK's offscreen window class (EGL unless set) and check it can work; return its name."""
    window = os.environ.setdefault(WINDOW_VARIABLE, EGL_WINDOW)
    _checked(window)
    return window
