/* SDL2 and OpenGL loaded on demand (sim/viewer/sdl_load.h): dlopen of
 * the two libraries the first time a window opens (OpenGL alone for a
 * context without a window), dlsym of each function the viewers call.
 * They stay loaded to the end of the process. */
#define EVO_SDL_LOAD_NO_NAMES
#include "viewer/sdl_load.h"

#include <dlfcn.h>
#include <string.h>

evo_sdl_api evo_sdl;

static int sdl_loaded, gl_loaded;

/* *slot = name's address in lib (h); 0, or -1 with err. */
static int load_symbol(void *h, const char *lib, const char *name,
		       void *slot, const char *what, evo_err *err)
{
	void *p = dlsym(h, name);
	if (!p)
		return evo_fail(err, "cannot open %s: %s has no %s (%s)", what,
				lib, name, dlerror());
	/* a function's address as dlsym gives it (POSIX: the same size) */
	memcpy(slot, &p, sizeof p);
	return 0;
}

/* dlopen lib; NULL with err saying it is missing. */
static void *open_library(const char *lib, const char *what, evo_err *err)
{
	void *h = dlopen(lib, RTLD_NOW | RTLD_GLOBAL);
	if (!h)
		evo_fail(err,
			 "cannot open %s: %s cannot be loaded (%s); a window "
			 "needs it installed, --headless runs without",
			 what, lib, dlerror());
	return h;
}

/* One function of an X-list from library h (lib), into evo_sdl; from a
 * function with h, lib, what and err in scope, which it leaves with -1
 * on a failure. */
#define EVO_LOAD(f)                                                            \
	if (load_symbol(h, lib, #f, &evo_sdl.f, what, err))                    \
		return -1;

/* The GL functions from lib (h), once. */
static int load_gl(void *h, const char *lib, const char *what, evo_err *err)
{
	EVO_GL_FUNCTIONS(EVO_LOAD)
	gl_loaded = 1;
	return 0;
}

int evo_gl_load_offscreen(const char *what, evo_err *err)
{
	if (gl_loaded)
		return 0;
	void *h = dlopen(EVO_OPENGL_LIB, RTLD_NOW | RTLD_GLOBAL);
	if (!h)
		return evo_fail(err,
				"cannot open %s: %s cannot be loaded (%s); "
				"install Debian's libopengl0",
				what, EVO_OPENGL_LIB, dlerror());
	return load_gl(h, EVO_OPENGL_LIB, what, err);
}

int evo_sdl_load(int gl, const char *what, evo_err *err)
{
	if (!sdl_loaded) {
		const char *lib = EVO_SDL_LIB;
		void *h = open_library(lib, what, err);
		if (!h)
			return -1;
		EVO_SDL_FUNCTIONS(EVO_LOAD)
		sdl_loaded = 1;
	}
	if (gl && !gl_loaded) {
		void *h = open_library(EVO_GL_LIB, what, err);
		if (!h || load_gl(h, EVO_GL_LIB, what, err))
			return -1;
	}
	return 0;
}
