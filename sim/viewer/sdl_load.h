/* SDL2 and OpenGL, loaded when a window opens (dlopen), not when evo
 * starts: linked in, SDL2 alone brings some fifty libraries (X11,
 * Wayland, PulseAudio, ...) that every `evo run --headless` then paid for
 * in loading time, and a learning run of XOR is over in a tenth of a
 * second. The viewer's code calls SDL and GL by their own names: after
 * this header, each name is the pointer evo_sdl_load filled in. */
#ifndef EVO_SDL_LOAD_H
#define EVO_SDL_LOAD_H

#include <SDL.h>
#include <SDL_opengl.h>

#include "base/err.h"

/* The library files, as a message names them when they cannot load. */
#define EVO_SDL_LIB "libSDL2-2.0.so.0"
#define EVO_GL_LIB "libGL.so.1"
/* GLVND's OpenGL without GLX (no X11 under it), for a context made by
 * EGL without a window (viewer/egl_offscreen.h). */
#define EVO_OPENGL_LIB "libOpenGL.so.0"

/* Every SDL function the viewers (and their test) call. */
#define EVO_SDL_FUNCTIONS(X)                                                   \
	X(SDL_CreateRenderer)                                                  \
	X(SDL_CreateTexture)                                                   \
	X(SDL_CreateWindow)                                                    \
	X(SDL_DestroyRenderer)                                                 \
	X(SDL_DestroyTexture)                                                  \
	X(SDL_DestroyWindow)                                                   \
	X(SDL_GL_CreateContext)                                                \
	X(SDL_GL_DeleteContext)                                                \
	X(SDL_GL_GetDrawableSize)                                              \
	X(SDL_GL_SetAttribute)                                                 \
	X(SDL_GL_SetSwapInterval)                                              \
	X(SDL_GL_SwapWindow)                                                   \
	X(SDL_GetError)                                                        \
	X(SDL_GetRendererOutputSize)                                           \
	X(SDL_InitSubSystem)                                                   \
	X(SDL_PollEvent)                                                       \
	X(SDL_PushEvent)                                                       \
	X(SDL_Quit)                                                            \
	X(SDL_QuitSubSystem)                                                   \
	X(SDL_RenderCopy)                                                      \
	X(SDL_RenderPresent)                                                   \
	X(SDL_RenderReadPixels)                                                \
	X(SDL_SetHintWithPriority)                                             \
	X(SDL_SetWindowTitle)                                                  \
	X(SDL_UpdateTexture)                                                   \
	X(SDL_WasInit)

/* Every OpenGL 1.x function the 3D view calls. */
#define EVO_GL_FUNCTIONS(X)                                                    \
	X(glBegin)                                                             \
	X(glBlendFunc)                                                         \
	X(glClear)                                                             \
	X(glClearColor)                                                        \
	X(glColor4d)                                                           \
	X(glColorMaterial)                                                     \
	X(glDepthMask)                                                         \
	X(glDisable)                                                           \
	X(glDrawPixels)                                                        \
	X(glEnable)                                                            \
	X(glEnd)                                                               \
	X(glFrustum)                                                           \
	X(glLightModelfv)                                                      \
	X(glLightfv)                                                           \
	X(glLineWidth)                                                         \
	X(glLoadIdentity)                                                      \
	X(glMatrixMode)                                                        \
	X(glMultMatrixd)                                                       \
	X(glNormal3d)                                                          \
	X(glNormal3dv)                                                         \
	X(glOrtho)                                                             \
	X(glPixelStorei)                                                       \
	X(glPixelZoom)                                                         \
	X(glPopMatrix)                                                         \
	X(glPushMatrix)                                                        \
	X(glRasterPos2i)                                                       \
	X(glReadPixels)                                                        \
	X(glRotated)                                                           \
	X(glScissor)                                                           \
	X(glTranslated)                                                        \
	X(glVertex3d)                                                          \
	X(glVertex3dv)                                                         \
	X(glViewport)

/* The loaded functions, each with the type its header declares. */
typedef struct evo_sdl_api {
#define EVO_SDL_MEMBER(f) __typeof__(f) *f;
	EVO_SDL_FUNCTIONS(EVO_SDL_MEMBER)
	EVO_GL_FUNCTIONS(EVO_SDL_MEMBER)
#undef EVO_SDL_MEMBER
} evo_sdl_api;

extern evo_sdl_api evo_sdl;

/* Load SDL2 (gl: and OpenGL too) once; later calls return at once.
 * 0, or -1 with err naming the library or function that is missing
 * (what: "the viewer", "the 3D view", for the message). */
int evo_sdl_load(int gl, const char *what, evo_err *err);

/* Load the OpenGL functions alone, from EVO_OPENGL_LIB, once (after
 * evo_sdl_load with gl, at once: the same functions). 0, or -1 with err
 * naming the library and its Debian package. */
int evo_gl_load_offscreen(const char *what, evo_err *err);

/* From here on, SDL_CreateWindow(...) is evo_sdl.SDL_CreateWindow(...). */
#ifndef EVO_SDL_LOAD_NO_NAMES
#define SDL_CreateRenderer evo_sdl.SDL_CreateRenderer
#define SDL_CreateTexture evo_sdl.SDL_CreateTexture
#define SDL_CreateWindow evo_sdl.SDL_CreateWindow
#define SDL_DestroyRenderer evo_sdl.SDL_DestroyRenderer
#define SDL_DestroyTexture evo_sdl.SDL_DestroyTexture
#define SDL_DestroyWindow evo_sdl.SDL_DestroyWindow
#define SDL_GL_CreateContext evo_sdl.SDL_GL_CreateContext
#define SDL_GL_DeleteContext evo_sdl.SDL_GL_DeleteContext
#define SDL_GL_GetDrawableSize evo_sdl.SDL_GL_GetDrawableSize
#define SDL_GL_SetAttribute evo_sdl.SDL_GL_SetAttribute
#define SDL_GL_SetSwapInterval evo_sdl.SDL_GL_SetSwapInterval
#define SDL_GL_SwapWindow evo_sdl.SDL_GL_SwapWindow
#define SDL_GetError evo_sdl.SDL_GetError
#define SDL_GetRendererOutputSize evo_sdl.SDL_GetRendererOutputSize
#define SDL_InitSubSystem evo_sdl.SDL_InitSubSystem
#define SDL_PollEvent evo_sdl.SDL_PollEvent
#define SDL_PushEvent evo_sdl.SDL_PushEvent
#define SDL_Quit evo_sdl.SDL_Quit
#define SDL_QuitSubSystem evo_sdl.SDL_QuitSubSystem
#define SDL_RenderCopy evo_sdl.SDL_RenderCopy
#define SDL_RenderPresent evo_sdl.SDL_RenderPresent
#define SDL_RenderReadPixels evo_sdl.SDL_RenderReadPixels
#define SDL_SetHintWithPriority evo_sdl.SDL_SetHintWithPriority
#define SDL_SetWindowTitle evo_sdl.SDL_SetWindowTitle
#define SDL_UpdateTexture evo_sdl.SDL_UpdateTexture
#define SDL_WasInit evo_sdl.SDL_WasInit
#define glBegin evo_sdl.glBegin
#define glBlendFunc evo_sdl.glBlendFunc
#define glClear evo_sdl.glClear
#define glClearColor evo_sdl.glClearColor
#define glColor4d evo_sdl.glColor4d
#define glColorMaterial evo_sdl.glColorMaterial
#define glDepthMask evo_sdl.glDepthMask
#define glDisable evo_sdl.glDisable
#define glDrawPixels evo_sdl.glDrawPixels
#define glEnable evo_sdl.glEnable
#define glEnd evo_sdl.glEnd
#define glFrustum evo_sdl.glFrustum
#define glLightModelfv evo_sdl.glLightModelfv
#define glLightfv evo_sdl.glLightfv
#define glLineWidth evo_sdl.glLineWidth
#define glLoadIdentity evo_sdl.glLoadIdentity
#define glMatrixMode evo_sdl.glMatrixMode
#define glMultMatrixd evo_sdl.glMultMatrixd
#define glNormal3d evo_sdl.glNormal3d
#define glNormal3dv evo_sdl.glNormal3dv
#define glOrtho evo_sdl.glOrtho
#define glPixelStorei evo_sdl.glPixelStorei
#define glPixelZoom evo_sdl.glPixelZoom
#define glPopMatrix evo_sdl.glPopMatrix
#define glPushMatrix evo_sdl.glPushMatrix
#define glRasterPos2i evo_sdl.glRasterPos2i
#define glReadPixels evo_sdl.glReadPixels
#define glRotated evo_sdl.glRotated
#define glScissor evo_sdl.glScissor
#define glTranslated evo_sdl.glTranslated
#define glVertex3d evo_sdl.glVertex3d
#define glVertex3dv evo_sdl.glVertex3dv
#define glViewport evo_sdl.glViewport
#endif

#endif
