/* Mesa's surfaceless EGL for an off-screen GL context
 * (sim/viewer/egl_offscreen.h): libEGL loaded with dlopen, a display on
 * the surfaceless platform, a pbuffer and a desktop GL context. */
#include "viewer/egl_offscreen.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <dlfcn.h>
#include <stdlib.h>
#include <string.h>

#include "viewer/sdl_load.h"

/* The EGL functions used, by their names without the egl prefix. */
#define EVO_EGL_FUNCTIONS(X)                                                   \
	X(BindAPI)                                                             \
	X(ChooseConfig)                                                        \
	X(CreateContext)                                                       \
	X(CreatePbufferSurface)                                                \
	X(DestroyContext)                                                      \
	X(DestroySurface)                                                      \
	X(GetError)                                                            \
	X(GetProcAddress)                                                      \
	X(Initialize)                                                          \
	X(MakeCurrent)                                                         \
	X(QueryString)                                                         \
	X(ReleaseThread)                                                       \
	X(Terminate)

static struct {
#define EVO_EGL_MEMBER(f) __typeof__(egl##f) *f;
	EVO_EGL_FUNCTIONS(EVO_EGL_MEMBER)
#undef EVO_EGL_MEMBER
	PFNEGLGETPLATFORMDISPLAYEXTPROC GetPlatformDisplayEXT;
	int loaded;
} egl;

struct evo_egl_context {
	EGLDisplay display;
	EGLSurface surface;
	EGLContext context;
};

#define WHAT "cannot draw 3D without a window"

/* libEGL and its functions, once; 0, or -1 with err. */
static int load_egl(evo_err *err)
{
	if (egl.loaded)
		return 0;
	void *h = dlopen(EVO_EGL_LIB, RTLD_NOW | RTLD_GLOBAL);
	if (!h)
		return evo_fail(err,
				WHAT ": %s cannot be loaded (%s); install "
				     "Debian's %s",
				EVO_EGL_LIB, dlerror(), EVO_EGL_PACKAGES);
#define EVO_EGL_LOAD(f)                                                        \
	{                                                                      \
		void *p = dlsym(h, "egl" #f);                                  \
		if (!p)                                                        \
			return evo_fail(err, WHAT ": %s has no egl" #f,        \
					EVO_EGL_LIB);                          \
		memcpy(&egl.f, &p, sizeof p);                                  \
	}
	EVO_EGL_FUNCTIONS(EVO_EGL_LOAD)
#undef EVO_EGL_LOAD
	/* the surfaceless platform is a client extension (no display yet) */
	const char *ext = egl.QueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
	if (!ext || !strstr(ext, "EGL_MESA_platform_surfaceless"))
		return evo_fail(err,
				WHAT ": %s has no surfaceless platform "
				     "(EGL_MESA_platform_surfaceless: Mesa's "
				     "EGL is missing); install Debian's %s",
				EVO_EGL_LIB, EVO_EGL_PACKAGES);
	void (*gpd)(void) = egl.GetProcAddress("eglGetPlatformDisplayEXT");
	if (!gpd)
		return evo_fail(err,
				WHAT ": %s has no eglGetPlatformDisplayEXT",
				EVO_EGL_LIB);
	memcpy(&egl.GetPlatformDisplayEXT, &gpd, sizeof gpd);
	egl.loaded = 1;
	return 0;
}

/* err for a failed EGL step, with EGL's error code. */
static evo_egl_context *failed(evo_egl_context *c, const char *step,
			       evo_err *err)
{
	evo_fail(err,
		 WHAT ": Mesa's EGL could not %s (EGL error 0x%04x); "
		      "install Debian's %s",
		 step, (unsigned)egl.GetError(), EVO_EGL_PACKAGES);
	evo_egl_close(c);
	return NULL;
}

evo_egl_context *evo_egl_open(int width, int height, evo_err *err)
{
	if (load_egl(err) ||
	    evo_gl_load_offscreen("the 3D view without a window", err))
		return NULL;
	evo_egl_context *c = calloc(1, sizeof *c);
	if (!c) {
		evo_fail(err, WHAT ": out of memory");
		return NULL;
	}
	c->display = egl.GetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA,
					       EGL_DEFAULT_DISPLAY, NULL);
	EGLint major, minor;
	if (c->display == EGL_NO_DISPLAY ||
	    !egl.Initialize(c->display, &major, &minor)) {
		c->display = EGL_NO_DISPLAY;
		return failed(c, "open a surfaceless display", err);
	}
	static const EGLint want[] = {EGL_SURFACE_TYPE,
				      EGL_PBUFFER_BIT,
				      EGL_RENDERABLE_TYPE,
				      EGL_OPENGL_BIT,
				      EGL_RED_SIZE,
				      8,
				      EGL_GREEN_SIZE,
				      8,
				      EGL_BLUE_SIZE,
				      8,
				      EGL_ALPHA_SIZE,
				      8,
				      EGL_DEPTH_SIZE,
				      24,
				      EGL_NONE};
	EGLConfig config;
	EGLint n = 0;
	if (!egl.ChooseConfig(c->display, want, &config, 1, &n) || n < 1)
		return failed(c, "find an RGB pbuffer with depth for OpenGL",
			      err);
	const EGLint size[] = {EGL_WIDTH, width, EGL_HEIGHT, height, EGL_NONE};
	c->surface = egl.CreatePbufferSurface(c->display, config, size);
	if (c->surface == EGL_NO_SURFACE)
		return failed(c, "make a pbuffer", err);
	if (!egl.BindAPI(EGL_OPENGL_API))
		return failed(c, "bind OpenGL", err);
	/* no attributes: the compatibility profile, which has the fixed
	 * functions the 3D view draws with */
	c->context =
	    egl.CreateContext(c->display, config, EGL_NO_CONTEXT, NULL);
	if (c->context == EGL_NO_CONTEXT)
		return failed(c, "make an OpenGL context", err);
	if (!egl.MakeCurrent(c->display, c->surface, c->surface, c->context))
		return failed(c, "make its context current", err);
	return c;
}

void evo_egl_close(evo_egl_context *c)
{
	if (!c)
		return;
	if (c->display != EGL_NO_DISPLAY) {
		egl.MakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE,
				EGL_NO_CONTEXT);
		if (c->context != EGL_NO_CONTEXT)
			egl.DestroyContext(c->display, c->context);
		if (c->surface != EGL_NO_SURFACE)
			egl.DestroySurface(c->display, c->surface);
		egl.Terminate(c->display);
		egl.ReleaseThread();
	}
	free(c);
}
