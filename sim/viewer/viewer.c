/* The DEMOSIM viewer, and DEMOREMOTE's panel: see viewer.h.
 *
 * Why a raster of evo's own and not SDL_Render's primitives: SDL 2 draws
 * no filled circles, no rotated boxes and no text, its software renderer
 * blends differently from its GL ones, and reading a GL back buffer after
 * a present is undefined. Drawing into memory gives the same pixels on
 * every machine, with or without a display, and one texture upload a
 * frame is cheap at these sizes.
 *
 * This file owns the camera and the drawing of the world; the panel and a
 * remote robot's frame are viewer_panel.c's, the window viewer_window.c's
 * (sharing viewer_internal.h). */
#include "viewer/viewer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "viewer/png.h"
#include "viewer/sdl_load.h"
#include "viewer/viewer_internal.h"
#include "world2d/query.h"

/* ---- camera ---------------------------------------------------------- */

static int panel_width(int w)
{
	return w < 3 * EVO_VIEW_PANEL_W ? w / 3 : EVO_VIEW_PANEL_W;
}

/* The bounding box of everything placed in the scene: its elements
 * (with their sizes), its bots (where they started, or are now) and, for
 * the scene as it started, its fixed obstacles and walls (not the grid's,
 * drawn afresh each episode). 0 when the scene is empty. */
static int scene_box(const evo_scene *sc, int at_start, double box[4])
{
	double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
#define GROW(px, py, r)                                                        \
	do {                                                                   \
		x0 = fmin(x0, (px) - (r));                                     \
		x1 = fmax(x1, (px) + (r));                                     \
		y0 = fmin(y0, (py) - (r));                                     \
		y1 = fmax(y1, (py) + (r));                                     \
	} while (0)
	for (int b = 0; b < sc->n_bots; b++) {
		evo_pose p = evo_body_pose(sc->world, sc->bot[b].body);
		if (at_start)
			GROW(sc->bot[b].def.x, sc->bot[b].def.y, 0);
		else
			GROW(p.x, p.y, 0);
	}
	for (int e = 0; e < sc->n_elements; e++) {
		const evo_element *el = &sc->element[e];
		double r = fmax(el->size, hypot(el->half_w, el->half_h));
		GROW(el->x, el->y, at_start && isfinite(r) ? r : 0);
	}
	for (int o = 0; at_start && o < sc->n_fixed_obstacles; o++) {
		const evo_obstacle *ob = &sc->obstacle[o];
		if (ob->shape == EVO_SHAPE_SEGMENT) {
			GROW(ob->x, ob->y, 0);
			GROW(ob->x2, ob->y2, 0);
		} else {
			GROW(ob->x, ob->y,
			     fmax(ob->radius, hypot(ob->half_w, ob->half_h)));
		}
	}
#undef GROW
	if (!(x0 <= x1 && y0 <= y1))
		return 0;
	box[0] = x0, box[1] = y0, box[2] = x1, box[3] = y1;
	return 1;
}

/* The middle of scene_box: what to look at when no bot is followed. */
static void scene_middle(const evo_scene *sc, int at_start, double *x,
			 double *y)
{
	double box[4];
	if (!scene_box(sc, at_start, box)) {
		*x = *y = 0;
		return;
	}
	*x = (box[0] + box[2]) / 2;
	*y = (box[1] + box[3]) / 2;
}

/* The zoom that shows box in a view of w x h pixels with 4% to spare
 * each side (1 shows EVO_VIEW_HALF_SPAN metres each way); 1 where none
 * does. */
static double zoom_to_fit(const double box[4], int w, int h)
{
	double world_w = w - panel_width(w);
	double side = world_w < h ? world_w : h;
	if (!(side > 0))
		return 1;
	/* pixels per metre that show the box */
	double fit = fmin(world_w / ((box[2] - box[0]) * 1.08),
			  h / ((box[3] - box[1]) * 1.08));
	double zoom = fit * (2 * EVO_VIEW_HALF_SPAN) / side;
	return isfinite(zoom) && zoom > 0 ? zoom : 1;
}

double evo_view_fit_zoom(const evo_scene *sc, int w, int h)
{
	double box[4];
	if (!scene_box(sc, 1, box))
		return 1;
	double zoom = zoom_to_fit(box, w, h);
	if (zoom < 4)
		return zoom < 1 ? zoom : 1;
	/* A small arena (an e-puck's, a few metres) would be a speck at
	 * zoom 1: the power of two that still shows all of it, with the
	 * obstacles its environment placed for this episode, which
	 * scene_box leaves out (a maze's walls are such). */
	for (int o = sc->n_fixed_obstacles; o < sc->n_obstacles; o++) {
		const evo_obstacle *ob = &sc->obstacle[o];
		if (ob->shape == EVO_SHAPE_SEGMENT) {
			box[0] = fmin(box[0], fmin(ob->x, ob->x2));
			box[2] = fmax(box[2], fmax(ob->x, ob->x2));
			box[1] = fmin(box[1], fmin(ob->y, ob->y2));
			box[3] = fmax(box[3], fmax(ob->y, ob->y2));
			continue;
		}
		double r = fmax(ob->radius, hypot(ob->half_w, ob->half_h));
		box[0] = fmin(box[0], ob->x - r);
		box[2] = fmax(box[2], ob->x + r);
		box[1] = fmin(box[1], ob->y - r);
		box[3] = fmax(box[3], ob->y + r);
	}
	zoom = zoom_to_fit(box, w, h);
	return zoom >= 4 ? fmin(64, exp2(floor(log2(zoom)))) : 1;
}

evo_view_camera evo_view_camera_for(const evo_scene *sc, int follow_bot,
				    double zoom, int w, int h)
{
	evo_view_camera c;
	c.world_w = w - panel_width(w);
	c.cx = c.world_w / 2.0;
	c.cy = h / 2.0;
	if (!(zoom > 0))
		zoom = 1;
	int side = c.world_w < h ? c.world_w : h;
	c.scale = (side > 0 ? side : 1) * zoom / (2 * EVO_VIEW_HALF_SPAN);
	if (follow_bot >= 0 && follow_bot < sc->n_bots) {
		evo_pose p = evo_body_pose(sc->world, sc->bot[follow_bot].body);
		c.x = p.x;
		c.y = p.y;
	} else {
		scene_middle(sc, follow_bot == EVO_VIEW_SCENE_START, &c.x,
			     &c.y);
	}
	return c;
}

void evo_view_to_screen(const evo_view_camera *cam, double x, double y,
			double *sx, double *sy)
{
	*sx = cam->cx + (x - cam->x) * cam->scale;
	*sy = cam->cy + (y - cam->y) * cam->scale;
}

/* A pixel index for a screen coordinate, kept where int arithmetic is
 * safe (a point may project anywhere). */
static int pix(double v)
{
	if (!(v > -1e6))
		return -1000000;
	if (v > 1e6)
		return 1000000;
	return (int)floor(v);
}

/* ---- the world ------------------------------------------------------- */

/* Twelve colours far from the world's own (obstacles grey, zones green,
 * objects orange, rays red) and from one another. */
static const uint32_t team_colours[EVO_SCENE_MAX_TEAMS] = {
    0x2F6FD0u, 0xD0342Fu, 0x2FA84Fu, 0x8E44C8u, 0x1AA8A8u, 0xC8A21Eu,
    0x6B4226u, 0xE05FA8u, 0x4A5A8Cu, 0x7FB01Eu, 0x303030u, 0x9C9CE0u};

uint32_t evo_view_team_colour(int k)
{
	if (k < 0 || k >= EVO_SCENE_MAX_TEAMS)
		return EVO_VIEW_BOT;
	return team_colours[k];
}

int evo_view_bot_at(const evo_scene *sc, double x, double y)
{
	int best = -1;
	double best_d = INFINITY;
	for (int b = 0; b < sc->n_bots; b++) {
		evo_pose p = evo_body_pose(sc->world, sc->bot[b].body);
		double d = hypot(p.x - x, p.y - y) - sc->bot[b].radius;
		if (d <= 0.5 && d < best_d) {
			best_d = d;
			best = b;
		}
	}
	return best;
}

#define GRID_LINE     0xE0DED6u
#define OBSTACLE_EDGE 0x5E5E5Eu
#define WALL_WIDTH 3.0 /* pixels: a maze's walls have no thickness */
#define ZONE_EDGE     0x2A8C3Au
#define ZONE_OFF      0xA8A8A8u
#define OBJECT_EDGE   0xA0560Au
#define BOT_EDGE      0x1C447Fu
#define PATCH_EDGE    0xB4B4B4u
#define LIGHT_EDGE    0x6B5A10u
#define GRIP	      0x333333u
#define SCALE_BAR     0x555555u

/* ---- the swarm's world ----------------------------------------------- */

/* In the order of evo_colour: red, yellow, green, cyan, blue, magenta,
 * white, black, each far from the view's own colours. */
static const uint32_t blob_colours[EVO_COLOUR_COUNT] = {
    0xD62728u, 0xFFD21Fu, 0x2CA02Cu, 0x17BECFu,
    0x1F3FB4u, 0xC83CC8u, 0xFFFFFFu, 0x202020u};

uint32_t evo_view_blob_colour(int colour)
{
	if (colour < 0 || colour >= EVO_COLOUR_COUNT)
		return EVO_VIEW_LIGHT;
	return blob_colours[colour];
}

int evo_view_colour_of(const evo_swarm *w, evo_blob_kind kind, int index)
{
	for (int i = 0; i < w->n_blobs; i++)
		if (w->blob[i].kind == kind && w->blob[i].index == index)
			return w->blob[i].colour;
	return -1;
}

uint32_t evo_view_grey(double grey)
{
	double g = grey > 1 ? 1 : grey > 0 ? grey : 0;
	uint32_t v = (uint32_t)lround(g * 255);
	return v << 16 | v << 8 | v;
}

/* A thing's colour: the one it was given, else `plain`. */
static uint32_t coloured(const evo_scene *sc, evo_blob_kind kind, int index,
			 uint32_t plain)
{
	int c = evo_view_colour_of(&sc->swarm, kind, index);
	return c < 0 ? plain : evo_view_blob_colour(c);
}

/* World-space corners of a box of half sides (hw, hh) turned by angle
 * about (x, y), in screen pixels. */
static void box_corners(const evo_view_camera *cam, double x, double y,
			double angle, double hw, double hh, double *sx,
			double *sy)
{
	double c = cos(angle), s = sin(angle);
	static const double ux[4] = {-1, 1, 1, -1}, uy[4] = {-1, -1, 1, 1};
	for (int k = 0; k < 4; k++) {
		double bx = ux[k] * hw, by = uy[k] * hh;
		evo_view_to_screen(cam, x + c * bx - s * by,
				   y + s * bx + c * by, &sx[k], &sy[k]);
	}
}

/* A disc of radius r metres at (x, y), filled and edged 1 pixel wide. */
static void edged_disc(evo_raster *im, const evo_view_camera *cam, double x,
		       double y, double r, uint32_t fill, uint32_t edge)
{
	double sx, sy;
	evo_view_to_screen(cam, x, y, &sx, &sy);
	evo_raster_fill_circle(im, sx, sy, r * cam->scale, fill, 255);
	evo_raster_circle(im, sx, sy, r * cam->scale, 1, edge, 255);
}

/* A box of half sides (hw, hh) turned by angle about (x, y), filled and
 * edged. */
static void edged_box(evo_raster *im, const evo_view_camera *cam, double x,
		      double y, double angle, double hw, double hh,
		      uint32_t fill, uint32_t edge)
{
	double bx[4], by[4];
	box_corners(cam, x, y, angle, hw, hh, bx, by);
	evo_raster_fill_polygon(im, bx, by, 4, fill, 255);
	evo_raster_polygon(im, bx, by, 4, edge, 255);
}

/* Faint lines every 10 m (every 50 m when they would crowd), so motion
 * shows while the camera follows a bot. */
static void draw_grid(evo_raster *im, const evo_view_camera *cam)
{
	double step = cam->scale * 10 >= 24 ? 10 : 50;
	double wx0 = cam->x - cam->cx / cam->scale;
	double wx1 = cam->x + (cam->world_w - cam->cx) / cam->scale;
	double wy0 = cam->y - cam->cy / cam->scale;
	double wy1 = cam->y + (im->h - cam->cy) / cam->scale;
	if (!isfinite(wx0) || !isfinite(wx1) || !isfinite(wy0) ||
	    !isfinite(wy1) || (wx1 - wx0) / step > 1000)
		return;
	for (double x = ceil(wx0 / step) * step; x <= wx1; x += step) {
		double sx, sy;
		evo_view_to_screen(cam, x, 0, &sx, &sy);
		evo_raster_fill_rect(im, pix(sx), 0, 1, im->h, GRID_LINE, 255);
	}
	for (double y = ceil(wy0 / step) * step; y <= wy1; y += step) {
		double sx, sy;
		evo_view_to_screen(cam, 0, y, &sx, &sy);
		evo_raster_fill_rect(im, 0, pix(sy), cam->world_w, 1, GRID_LINE,
				     255);
	}
}

/* A floor patch, filled with its grey level and edged faintly, so that a
 * white one shows on the background. */
static void draw_patch(evo_raster *im, const evo_view_camera *cam,
		       const evo_patch *pa)
{
	uint32_t grey = evo_view_grey(pa->grey);
	if (pa->circle)
		edged_disc(im, cam, pa->x, pa->y, pa->radius, grey, PATCH_EDGE);
	else
		edged_box(im, cam, pa->x, pa->y, pa->yaw, pa->hx, pa->hy, grey,
			  PATCH_EDGE);
}

/* A light: a disc in its colour, edged dark, and a ring where a light
 * sensor facing it reads 1 (sqrt(intensity) metres away). */
static void draw_light(evo_raster *im, const evo_view_camera *cam,
		       const evo_scene *sc, int i)
{
	const evo_light *l = &sc->swarm.light[i];
	uint32_t c = coloured(sc, EVO_BLOB_LIGHT, i, EVO_VIEW_LIGHT);
	double sx, sy;
	evo_view_to_screen(cam, l->pos[0], l->pos[1], &sx, &sy);
	evo_raster_circle(im, sx, sy, sqrt(l->intensity) * cam->scale, 1, c,
			  160);
	evo_raster_fill_circle(im, sx, sy, EVO_VIEW_LIGHT_RADIUS, c, 255);
	evo_raster_circle(im, sx, sy, EVO_VIEW_LIGHT_RADIUS, 1, LIGHT_EDGE,
			  255);
}

/* An element given a colour that the obstacles draw grey (a cylinder or
 * a box): drawn again over them in its colour. */
static void draw_coloured_element(evo_raster *im, const evo_view_camera *cam,
				  const evo_scene *sc, int e)
{
	const evo_element *el = &sc->element[e];
	int c = evo_view_colour_of(&sc->swarm, EVO_BLOB_ELEMENT, e);
	if (c < 0)
		return;
	uint32_t rgb = evo_view_blob_colour(c);
	if (el->kind == EVO_PIECE_CYLINDER)
		edged_disc(im, cam, el->x, el->y, el->size, rgb, OBSTACLE_EDGE);
	else if (el->kind == EVO_PIECE_BOX)
		edged_box(im, cam, el->x, el->y, el->angle, el->half_w,
			  el->half_h, rgb, OBSTACLE_EDGE);
}

static void draw_obstacle(evo_raster *im, const evo_view_camera *cam,
			  const evo_obstacle *o)
{
	if (o->shape == EVO_SHAPE_CIRCLE) {
		edged_disc(im, cam, o->x, o->y, o->radius, EVO_VIEW_OBSTACLE,
			   OBSTACLE_EDGE);
		return;
	}
	if (o->shape == EVO_SHAPE_SEGMENT) {
		double ax, ay, bx, by;
		evo_view_to_screen(cam, o->x, o->y, &ax, &ay);
		evo_view_to_screen(cam, o->x2, o->y2, &bx, &by);
		evo_raster_thick_line(im, ax, ay, bx, by, WALL_WIDTH,
				      EVO_VIEW_WALL, 255);
		return;
	}
	edged_box(im, cam, o->x, o->y, o->angle, o->half_w, o->half_h,
		  EVO_VIEW_OBSTACLE, OBSTACLE_EDGE);
}

static void draw_zone(evo_raster *im, const evo_view_camera *cam,
		      const evo_scene *sc, int e)
{
	const evo_element *z = &sc->element[e];
	double bx[4], by[4];
	box_corners(cam, z->x, z->y, z->angle, z->size, z->size, bx, by);
	if (!z->active) {
		evo_raster_polygon(im, bx, by, 4, ZONE_OFF, 255);
		return;
	}
	evo_raster_fill_polygon(im, bx, by, 4,
				coloured(sc, EVO_BLOB_ELEMENT, e, EVO_VIEW_ZONE),
				EVO_VIEW_ZONE_ALPHA);
	evo_raster_polygon(im, bx, by, 4, ZONE_EDGE, 255);
}

static void draw_object(evo_raster *im, const evo_view_camera *cam,
			const evo_scene *sc, int e)
{
	const evo_element *o = &sc->element[e];
	double x = o->x, y = o->y;
	if (evo_body_valid(sc->world, o->body)) {
		evo_pose p = evo_body_pose(sc->world, o->body);
		x = p.x;
		y = p.y;
	}
	double sx, sy, r = o->size * cam->scale;
	evo_view_to_screen(cam, x, y, &sx, &sy);
	/* A delivered object is off the world until the next episode: a
	 * faint outline where it was says it is gone, not lost. */
	if (!o->active) {
		evo_raster_circle(im, sx, sy, r, 1, OBJECT_EDGE, 70);
		return;
	}
	evo_raster_fill_circle(im, sx, sy, r,
			       coloured(sc, EVO_BLOB_ELEMENT, e, EVO_VIEW_OBJECT),
			       255);
	evo_raster_circle(im, sx, sy, r, 1, OBJECT_EDGE, 255);
	if (o->held_by >= 0)
		evo_raster_circle(im, sx, sy, r + 3, 2, EVO_VIEW_HELD, 255);
}

/* A proximity sensor's fan, ray by ray as sim/world2d/sensors.c casts it: from
 * the sensor's point, ray i at angle - arc + i * 2 arc / (n - 1) in the
 * bot's frame, `range` long, stopped at its hit fraction. */
static void draw_rays(evo_raster *im, const evo_view_camera *cam,
		      const evo_scene *sc, int b, const evo_sensor *se)
{
	const evo_sensor_def *d = &se->def;
	int n = d->rays < 1		      ? 1
		: d->rays > EVO_PROX_MAX_RAYS ? EVO_PROX_MAX_RAYS
					      : d->rays;
	double arc = n > 1 ? fabs(d->arc) : 0;
	double step = n > 1 ? 2 * arc / (n - 1) : 0;
	evo_pose p = evo_body_pose(sc->world, sc->bot[b].body);
	double px, py, sx, sy;
	evo_bot_to_world(sc, b, d->x, d->y, &px, &py);
	evo_view_to_screen(cam, px, py, &sx, &sy);
	for (int i = 0; i < n; i++) {
		double a = p.angle + d->angle - arc + i * step;
		double f = se->ray[i];
		int hit = f < 1;
		if (!(f >= 0) || f > 1)
			f = 1;
		double ex, ey;
		evo_view_to_screen(cam, px + cos(a) * d->range * f,
				   py + sin(a) * d->range * f, &ex, &ey);
		evo_raster_line(im, pix(sx), pix(sy), pix(ex), pix(ey),
				EVO_VIEW_RAY_HIT,
				hit ? 255 : EVO_VIEW_RAY_CLEAR_ALPHA);
		if (hit)
			evo_raster_fill_rect(im, pix(ex) - 1, pix(ey) - 1, 3, 3,
					     EVO_VIEW_RAY_HIT, 255);
	}
}

static void draw_bot(evo_raster *im, const evo_view_camera *cam,
		     const evo_scene *sc, int b)
{
	const evo_bot *bot = &sc->bot[b];
	evo_pose p = evo_body_pose(sc->world, bot->body);
	double sx, sy, r = bot->radius * cam->scale;
	evo_view_to_screen(cam, p.x, p.y, &sx, &sy);
	evo_raster_fill_circle(im, sx, sy, r,
			       coloured(sc, EVO_BLOB_BOT, b,
					evo_view_team_colour(bot->team)),
			       255);
	evo_raster_circle(im, sx, sy, r, r > 8 ? 2 : 1, BOT_EDGE, 255);
	double hx, hy;
	evo_view_to_screen(cam, p.x + cos(p.angle) * bot->radius,
			   p.y + sin(p.angle) * bot->radius, &hx, &hy);
	evo_raster_thick_line(im, sx, sy, hx, hy, r > 8 ? 2 : 1,
			      EVO_VIEW_HEADING, 255);
}

/* Each claw: a dark mark where it grips, joined to what it holds. */
static void draw_claws(evo_raster *im, const evo_view_camera *cam,
		       const evo_scene *sc, int b)
{
	const evo_bot *bot = &sc->bot[b];
	for (int k = 0; k < bot->n_actuators; k++) {
		const evo_actuator *a = &bot->actuator[k];
		if (a->def.kind != EVO_ACT_CLAW)
			continue;
		double cx, cy, sx, sy;
		evo_bot_to_world(sc, b, a->def.x, a->def.y, &cx, &cy);
		evo_view_to_screen(cam, cx, cy, &sx, &sy);
		if (a->held >= 0 && a->held < sc->n_elements) {
			const evo_element *o = &sc->element[a->held];
			double ox = o->x, oy = o->y, tx, ty;
			if (evo_body_valid(sc->world, o->body)) {
				evo_pose op = evo_body_pose(sc->world, o->body);
				ox = op.x;
				oy = op.y;
			}
			evo_view_to_screen(cam, ox, oy, &tx, &ty);
			evo_raster_thick_line(im, sx, sy, tx, ty, 2, GRIP, 255);
		}
		evo_raster_fill_rect(im, pix(sx) - 2, pix(sy) - 2, 5, 5, GRIP,
				     255);
	}
}

/* A bar of a round length (1, 2 or 5 times a power of ten metres) near
 * 100 pixels, at the bottom left of the world area. */
static void draw_scale_bar(evo_raster *im, const evo_view_camera *cam)
{
	double want = 100 / cam->scale;
	if (!(want > 1e-3 && want < 1e6))
		return;
	double unit = pow(10, floor(log10(want)));
	double len = want / unit >= 5	? 5 * unit
		     : want / unit >= 2 ? 2 * unit
					: unit;
	int px = (int)lround(len * cam->scale);
	int x = 12, y = im->h - 14;
	evo_raster_fill_rect(im, x, y, px, 2, SCALE_BAR, 255);
	evo_raster_fill_rect(im, x, y - 4, 1, 6, SCALE_BAR, 255);
	evo_raster_fill_rect(im, x + px - 1, y - 4, 1, 6, SCALE_BAR, 255);
	char label[32];
	snprintf(label, sizeof label, "%g m", len);
	evo_raster_text(im, x + px + 6, y - 5, label, SCALE_BAR, 1);
}

/* A ring around the selected bot. */
static void draw_selection(evo_raster *im, const evo_view_camera *cam,
			   const evo_scene *sc, int b)
{
	if (b < 0 || b >= sc->n_bots)
		return;
	evo_pose p = evo_body_pose(sc->world, sc->bot[b].body);
	double sx, sy, r = sc->bot[b].radius * cam->scale;
	evo_view_to_screen(cam, p.x, p.y, &sx, &sy);
	evo_raster_circle(im, sx, sy, r + 4, 2, EVO_VIEW_SELECTED, 255);
}

/* The path of the episode so far, a line 2 pixels wide. */
static void draw_trail(evo_raster *im, const evo_view_camera *cam,
		       const evo_viewer_panel *p)
{
	if (!p || p->n_trail < 2 || !p->trail_x || !p->trail_y)
		return;
	double ax, ay;
	evo_view_to_screen(cam, p->trail_x[0], p->trail_y[0], &ax, &ay);
	for (int i = 1; i < p->n_trail; i++) {
		double bx, by;
		evo_view_to_screen(cam, p->trail_x[i], p->trail_y[i], &bx, &by);
		evo_raster_thick_line(im, ax, ay, bx, by, 2, EVO_VIEW_TRAIL,
				      255);
		ax = bx;
		ay = by;
	}
}

void evo_view_render(evo_raster *im, const evo_scene *sc,
		     const evo_view_camera *cam, const evo_viewer_panel *p)
{
	evo_raster_clear(im, EVO_VIEW_BACKGROUND);
	draw_grid(im, cam);
	for (int i = 0; i < sc->swarm.n_patches; i++)
		draw_patch(im, cam, &sc->swarm.patch[i]);
	for (int e = 0; e < sc->n_elements; e++)
		if (sc->element[e].kind == EVO_PIECE_ZONE)
			draw_zone(im, cam, sc, e);
	for (int o = 0; o < sc->n_obstacles; o++)
		draw_obstacle(im, cam, &sc->obstacle[o]);
	for (int e = 0; e < sc->n_elements; e++) {
		draw_coloured_element(im, cam, sc, e);
		if (sc->element[e].kind == EVO_PIECE_OBJECT &&
		    sc->element[e].held_by < 0)
			draw_object(im, cam, sc, e);
	}
	draw_trail(im, cam, p);
	for (int b = 0; b < sc->n_bots; b++)
		draw_bot(im, cam, sc, b);
	/* Rays over the bots: a sensor placed inside the body still shows
	 * its whole fan. An idle sensor (nothing reads it) is not sampled,
	 * so it has no rays to show. */
	for (int b = 0; b < sc->n_bots; b++)
		for (int s = 0; s < sc->bot[b].n_sensors; s++)
			if (sc->bot[b].sensor[s].def.kind ==
				    EVO_SENSE_PROXIMITY &&
			    !sc->bot[b].sensor[s].idle)
				draw_rays(im, cam, sc, b,
					  &sc->bot[b].sensor[s]);
	/* Held objects over the bot that carries them. */
	for (int e = 0; e < sc->n_elements; e++)
		if (sc->element[e].kind == EVO_PIECE_OBJECT &&
		    sc->element[e].held_by >= 0)
			draw_object(im, cam, sc, e);
	for (int b = 0; b < sc->n_bots; b++)
		draw_claws(im, cam, sc, b);
	/* Lights over everything: a swarm gathers under them. */
	for (int i = 0; i < sc->swarm.n_lights; i++)
		draw_light(im, cam, sc, i);
	/* Names only where there is more than one bot to tell apart. */
	if (sc->n_bots > 1)
		for (int b = 0; b < sc->n_bots; b++) {
			evo_pose bp = evo_body_pose(sc->world, sc->bot[b].body);
			double sx, sy;
			evo_view_to_screen(cam, bp.x, bp.y + sc->bot[b].radius,
					   &sx, &sy);
			int tw = evo_raster_text_width(sc->bot[b].name, 1);
			evo_raster_text(im, pix(sx) - tw / 2, pix(sy) + 4,
					sc->bot[b].name, BOT_EDGE, 1);
		}
	if (p && p->bot_name)
		draw_selection(im, cam, sc, p->bot);
	draw_scale_bar(im, cam);
	view_draw_panel(im, sc, cam, p);
}