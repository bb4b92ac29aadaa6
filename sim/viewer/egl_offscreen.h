/* An OpenGL context without a window: Mesa's EGL on its "surfaceless"
 * platform (EGL_MESA_platform_surfaceless), drawing into a pbuffer of a
 * fixed size with a depth buffer, on the GPU's render node where there is
 * one and on llvmpipe (the same software rasterizer Xvfb's windows get)
 * where there is none. It needs no display and no X server: a 3D
 * `--screenshot` or `--record` draws through it.
 *
 * Why EGL and not OSMesa: Debian's Mesa ships EGL beside its GL drivers
 * (libegl1, libegl-mesa0), and a context made by it is an ordinary one,
 * drawn in by the same driver and the same calls as a window's (GLVND's
 * libOpenGL dispatches to it); OSMesa is a separate build of Mesa
 * (libosmesa6) that Mesa has since dropped.
 *
 * libEGL.so.1 is loaded with dlopen when a context is opened, as SDL is
 * for a window (viewer/sdl_load.h): a run that draws no 3D never maps it.
 * The GL functions come from libOpenGL.so.0 (evo_gl_load_offscreen). */
#ifndef EVO_EGL_OFFSCREEN_H
#define EVO_EGL_OFFSCREEN_H

#include "base/err.h"

typedef struct evo_egl_context evo_egl_context;

/* The libraries, as messages name them, and the Debian packages that
 * hold them. */
#define EVO_EGL_LIB	 "libEGL.so.1"
#define EVO_EGL_PACKAGES "libegl1 libegl-mesa0 libgl1-mesa-dri"

/* A width x height off-screen GL context (compatibility profile, RGBA 8
 * bits each as a window's visual has them, so that the same drawing gives
 * the same pixels; 24-bit depth), made current on the calling thread; NULL
 * with err naming the library or the step that failed, and the Debian
 * packages to install. */
evo_egl_context *evo_egl_open(int width, int height, evo_err *err);

/* Release the context and its surface (NULL: nothing). */
void evo_egl_close(evo_egl_context *c);

#endif
