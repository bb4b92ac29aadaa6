/* The viewer's window (sim/viewer/viewer.h): SDL2 and OpenGL loaded at
 * run time (sdl_load.h), the raster shown as one texture a frame, keys
 * and clicks turned into actions, screenshots. */
#include "viewer/viewer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "viewer/png.h"
#include "viewer/sdl_load.h"
#include "viewer/viewer_internal.h"
#include "world2d/query.h"

struct evo_viewer {
	SDL_Window *window;
	SDL_Renderer *renderer;
	SDL_Texture *texture; /* the frame's size, streaming RGB24 */
	evo_raster frame;
	evo_view_camera cam;
	double zoom;
	int drawn;
	char title[128];
	/* the free camera's centre (has_free once set), the last click, and
	 * a drag under way */
	int has_free;
	double free_x, free_y;
	double click_x, click_y;
	int pressed, dragged;
	int press_x, press_y;
};

void *view_start_sdl(int gl, const char *what, int *w, int *h, size_t size,
		     evo_err *err)
{
	if (*w <= 0 || *h <= 0) {
		*w = 1024;
		*h = 720;
	}
	if (evo_sdl_load(gl, what, err))
		return NULL;
	/* Left alone, SDL backs the window of a software renderer with a
	 * GL texture, loading Mesa (llvmpipe under Xvfb) for each window
	 * only to copy a bitmap. Plain X11 (XShm) images are enough; at
	 * default priority, so SDL_FRAMEBUFFER_ACCELERATION in the
	 * environment still wins. */
	if (!gl)
		SDL_SetHintWithPriority(SDL_HINT_FRAMEBUFFER_ACCELERATION, "0",
					SDL_HINT_DEFAULT);
	if (SDL_InitSubSystem(SDL_INIT_VIDEO) != 0) {
		evo_fail(err,
			 "cannot open %s: %s (no display? set DISPLAY, or run "
			 "with --headless)",
			 what, SDL_GetError());
		return NULL;
	}
	void *v = calloc(1, size);
	if (!v) {
		evo_fail(err, "cannot open %s: out of memory", what);
		SDL_QuitSubSystem(SDL_INIT_VIDEO);
	}
	return v;
}

evo_viewer *evo_viewer_open(int width, int height, evo_err *err)
{
	evo_viewer *v = view_start_sdl(0, "the viewer", &width, &height,
				       sizeof *v, err);
	if (!v)
		return NULL;
	v->zoom = 1;
	v->window = SDL_CreateWindow("evo", SDL_WINDOWPOS_CENTERED,
				     SDL_WINDOWPOS_CENTERED, width, height,
				     SDL_WINDOW_RESIZABLE);
	if (!v->window) {
		evo_fail(err, "cannot open the viewer's window: %s",
			 SDL_GetError());
		evo_viewer_close(v);
		return NULL;
	}
	/* The software renderer first: it needs no GL (Xvfb, remote X) and
	 * reads back exactly what it shows. */
	v->renderer = SDL_CreateRenderer(v->window, -1, SDL_RENDERER_SOFTWARE);
	if (!v->renderer)
		v->renderer = SDL_CreateRenderer(v->window, -1, 0);
	if (!v->renderer) {
		evo_fail(err, "cannot make a renderer for the viewer: %s",
			 SDL_GetError());
		evo_viewer_close(v);
		return NULL;
	}
	return v;
}

void evo_viewer_close(evo_viewer *v)
{
	if (!v)
		return;
	if (v->texture)
		SDL_DestroyTexture(v->texture);
	if (v->renderer)
		SDL_DestroyRenderer(v->renderer);
	if (v->window)
		SDL_DestroyWindow(v->window);
	evo_raster_free(&v->frame);
	free(v);
	SDL_QuitSubSystem(SDL_INIT_VIDEO);
	/* Whoever started SDL for video alone (evo does) also ends it, so
	 * SDL's global state does not outlive the last viewer. */
	if (SDL_WasInit(SDL_INIT_EVERYTHING) == 0)
		SDL_Quit();
}

/* Frame and texture at the renderer's size, made again after a resize. */
static int fit_frame(evo_viewer *v)
{
	int w, h;
	if (SDL_GetRendererOutputSize(v->renderer, &w, &h) != 0 || w < 1 ||
	    h < 1)
		return -1;
	if (v->texture && v->frame.w == w && v->frame.h == h)
		return 0;
	if (v->texture)
		SDL_DestroyTexture(v->texture);
	v->texture = NULL;
	evo_raster_free(&v->frame);
	if (evo_raster_init(&v->frame, w, h, NULL))
		return -1;
	v->texture = SDL_CreateTexture(v->renderer, SDL_PIXELFORMAT_RGB24,
				       SDL_TEXTUREACCESS_STREAMING, w, h);
	if (!v->texture) {
		evo_raster_free(&v->frame);
		return -1;
	}
	return 0;
}

/* Put the frame on the renderer's target (not yet shown). */
static int blit(evo_viewer *v)
{
	if (SDL_UpdateTexture(v->texture, NULL, v->frame.pixels,
			      v->frame.w * 3) != 0)
		return -1;
	if (SDL_RenderCopy(v->renderer, v->texture, NULL, NULL) != 0)
		return -1;
	return 0;
}

void evo_viewer_draw(evo_viewer *v, const evo_scene *sc, int follow_bot,
		     const evo_viewer_panel *p)
{
	if (fit_frame(v))
		return; /* a minimised window or no memory: skip the frame */
	if (p && p->title && strncmp(p->title, v->title, sizeof v->title)) {
		snprintf(v->title, sizeof v->title, "%s", p->title);
		char t[160];
		snprintf(t, sizeof t, "evo - %s", v->title);
		SDL_SetWindowTitle(v->window, t);
	}
	v->cam = evo_view_camera_for(sc, follow_bot, v->zoom, v->frame.w,
				     v->frame.h);
	/* Following, the free camera waits where the bot is; free, it
	 * stays where it was put. */
	if (follow_bot >= 0 && follow_bot < sc->n_bots) {
		v->free_x = v->cam.x;
		v->free_y = v->cam.y;
		v->has_free = 1;
	} else if (follow_bot == -1) {
		if (!v->has_free) {
			v->free_x = v->cam.x;
			v->free_y = v->cam.y;
			v->has_free = 1;
		}
		v->cam.x = v->free_x;
		v->cam.y = v->free_y;
	}
	evo_view_render(&v->frame, sc, &v->cam, p);
	if (blit(v) == 0) {
		SDL_RenderPresent(v->renderer);
		v->drawn = 1;
	}
}

void evo_viewer_draw_remote(evo_viewer *v, const evo_view_remote *p)
{
	if (fit_frame(v))
		return;
	if (p && p->title && strncmp(p->title, v->title, sizeof v->title)) {
		snprintf(v->title, sizeof v->title, "%s", p->title);
		char t[160];
		snprintf(t, sizeof t, "evo - %s", v->title);
		SDL_SetWindowTitle(v->window, t);
	}
	evo_view_render_remote(&v->frame, p);
	if (blit(v) == 0) {
		SDL_RenderPresent(v->renderer);
		v->drawn = 1;
	}
}

evo_view_camera evo_viewer_camera(const evo_viewer *v)
{
	return v->cam;
}

void evo_viewer_clicked(const evo_viewer *v, double *x, double *y)
{
	*x = v->click_x;
	*y = v->click_y;
}

void evo_viewer_look_at(evo_viewer *v, double x, double y)
{
	if (!isfinite(x) || !isfinite(y))
		return;
	v->free_x = x;
	v->free_y = y;
	v->has_free = 1;
}

void evo_viewer_zoom(evo_viewer *v, double factor)
{
	if (!(factor > 0))
		return;
	v->zoom *= factor;
	if (v->zoom < 1.0 / 16)
		v->zoom = 1.0 / 16;
	if (v->zoom > 64)
		v->zoom = 64;
}

evo_view_action evo_viewer_poll(evo_viewer *v)
{
	SDL_Event ev;
	while (SDL_PollEvent(&ev)) {
		evo_view_action a = view_action_of(&ev);
		if (a != EVO_VIEW_NONE)
			return a;
		view_zoom z = view_zoom_of(&ev);
		if (z == VIEW_ZOOM_HOME)
			v->zoom = 1;
		else if (z != VIEW_ZOOM_NONE)
			evo_viewer_zoom(v, z == VIEW_ZOOM_IN ? 1.25 : 0.8);
		if (z != VIEW_ZOOM_NONE || ev.type == SDL_MOUSEWHEEL)
			continue;
		/* A click on the world selects; a drag moves the free
		 * camera (and frees it). */
		if (ev.type == SDL_MOUSEBUTTONDOWN &&
		    ev.button.button == SDL_BUTTON_LEFT &&
		    ev.button.x < v->cam.world_w) {
			v->pressed = 1;
			v->dragged = 0;
			v->press_x = ev.button.x;
			v->press_y = ev.button.y;
			continue;
		}
		if (ev.type == SDL_MOUSEMOTION && v->pressed &&
		    v->cam.scale > 0) {
			int far = abs(ev.motion.x - v->press_x) +
				      abs(ev.motion.y - v->press_y) >
				  4;
			if (!v->dragged && !far)
				continue;
			int first = !v->dragged;
			if (first) {
				/* the frame's view, from where the drag
				 * started */
				v->free_x = v->cam.x;
				v->free_y = v->cam.y;
				v->has_free = 1;
			}
			v->dragged = 1;
			v->free_x -= ev.motion.xrel / v->cam.scale;
			v->free_y -= ev.motion.yrel / v->cam.scale;
			if (first)
				return EVO_VIEW_FREE;
			continue;
		}
		if (ev.type == SDL_MOUSEBUTTONUP &&
		    ev.button.button == SDL_BUTTON_LEFT && v->pressed) {
			v->pressed = 0;
			if (v->dragged || v->cam.scale <= 0)
				continue;
			v->click_x =
			    v->cam.x +
			    (ev.button.x + 0.5 - v->cam.cx) / v->cam.scale;
			v->click_y =
			    v->cam.y +
			    (ev.button.y + 0.5 - v->cam.cy) / v->cam.scale;
			return EVO_VIEW_SELECT;
		}
		if (ev.type == SDL_KEYDOWN && ev.key.keysym.sym == SDLK_TAB)
			return EVO_VIEW_NEXT_BOT;
	}
	return EVO_VIEW_NONE;
}

evo_view_action view_action_of(const SDL_Event *ev)
{
	if (ev->type == SDL_QUIT || (ev->type == SDL_WINDOWEVENT &&
				     ev->window.event == SDL_WINDOWEVENT_CLOSE))
		return EVO_VIEW_QUIT;
	if (ev->type != SDL_KEYDOWN)
		return EVO_VIEW_NONE;
	return evo_view_key(ev->key.keysym.sym, ev->key.repeat);
}

view_zoom view_zoom_of(const SDL_Event *ev)
{
	if (ev->type == SDL_MOUSEWHEEL)
		return ev->wheel.y > 0	 ? VIEW_ZOOM_IN
		       : ev->wheel.y < 0 ? VIEW_ZOOM_OUT
					 : VIEW_ZOOM_NONE;
	if (ev->type != SDL_KEYDOWN)
		return VIEW_ZOOM_NONE;
	switch (ev->key.keysym.sym) {
	case SDLK_PLUS:
	case SDLK_EQUALS:
	case SDLK_KP_PLUS:
		return VIEW_ZOOM_IN;
	case SDLK_MINUS:
	case SDLK_KP_MINUS:
		return VIEW_ZOOM_OUT;
	case SDLK_0:
	case SDLK_KP_0:
		return VIEW_ZOOM_HOME;
	default:
		return VIEW_ZOOM_NONE;
	}
}

evo_view_action evo_view_key(int sym, int repeat)
{
	switch (sym) {
	case SDLK_n:
	case SDLK_RIGHT:
		return EVO_VIEW_STEP;
	case SDLK_UP:
	case SDLK_RIGHTBRACKET:
		return EVO_VIEW_FASTER;
	case SDLK_DOWN:
	case SDLK_LEFTBRACKET:
		return EVO_VIEW_SLOWER;
	}
	if (repeat)
		return EVO_VIEW_NONE;
	switch (sym) {
	case SDLK_q:
	case SDLK_ESCAPE:
		return EVO_VIEW_QUIT;
	case SDLK_SPACE:
	case SDLK_p:
		return EVO_VIEW_PAUSE;
	case SDLK_r:
		return EVO_VIEW_RESET;
	case SDLK_s:
		return EVO_VIEW_SCREENSHOT;
	case SDLK_c:
		return EVO_VIEW_CAMERA;
	default:
		return EVO_VIEW_NONE;
	}
}

int evo_viewer_screenshot(evo_viewer *v, const char *png_path, evo_err *err)
{
	if (!v->drawn)
		return evo_fail(err, "%s: no frame drawn yet", png_path);
	int w = v->frame.w, h = v->frame.h, tw, th;
	/* Resized since the last frame: the target no longer holds it, and
	 * reading it into a buffer of the frame's size would not fit. */
	if (SDL_GetRendererOutputSize(v->renderer, &tw, &th) != 0 || tw != w ||
	    th != h)
		return evo_fail(err,
				"%s: the window changed size since the last "
				"frame; draw one first",
				png_path);
	uint8_t *px = malloc((size_t)w * h * 3);
	if (!px)
		return evo_fail(err, "%s: out of memory", png_path);
	/* After a present the target's contents are undefined on some
	 * renderers: put the frame back, then read the target. */
	if (blit(v) != 0 ||
	    SDL_RenderReadPixels(v->renderer, NULL, SDL_PIXELFORMAT_RGB24, px,
				 w * 3) != 0) {
		free(px);
		return evo_fail(err, "%s: cannot read the window back: %s",
				png_path, SDL_GetError());
	}
	int rc = evo_png_write(png_path, px, w, h, 3, err);
	free(px);
	return rc;
}