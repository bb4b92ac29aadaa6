/* The DEMOSIM viewer, and DEMOREMOTE's panel: see viewer.h.
 *
 * Why a raster of evo's own and not SDL_Render's primitives: SDL 2 draws
 * no filled circles, no rotated boxes and no text, its software renderer
 * blends differently from its GL ones, and reading a GL back buffer after
 * a present is undefined. Drawing into memory gives the same pixels on
 * every machine, with or without a display, and one texture upload a
 * frame is cheap at these sizes. */
#include "viewer/viewer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


#include "viewer/png.h"
#include "viewer/sdl_load.h"
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

double evo_view_fit_zoom(const evo_scene *sc, int w, int h)
{
	double box[4];
	if (!scene_box(sc, 1, box))
		return 1;
	double world_w = w - panel_width(w);
	double side = world_w < h ? world_w : h;
	if (!(side > 0))
		return 1;
	/* pixels per metre that show the box with 4% to spare each side */
	double fit = fmin(world_w / ((box[2] - box[0]) * 1.08),
			  h / ((box[3] - box[1]) * 1.08));
	double zoom = fit * (2 * EVO_VIEW_HALF_SPAN) / side;
	return isfinite(zoom) && zoom > 0 && zoom < 1 ? zoom : 1;
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
#define GRIP	      0x333333u
#define SCALE_BAR     0x555555u

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

static void draw_obstacle(evo_raster *im, const evo_view_camera *cam,
			  const evo_obstacle *o)
{
	if (o->shape == EVO_SHAPE_CIRCLE) {
		double sx, sy, r = o->radius * cam->scale;
		evo_view_to_screen(cam, o->x, o->y, &sx, &sy);
		evo_raster_fill_circle(im, sx, sy, r, EVO_VIEW_OBSTACLE, 255);
		evo_raster_circle(im, sx, sy, r, 1, OBSTACLE_EDGE, 255);
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
	double bx[4], by[4];
	box_corners(cam, o->x, o->y, o->angle, o->half_w, o->half_h, bx, by);
	evo_raster_fill_polygon(im, bx, by, 4, EVO_VIEW_OBSTACLE, 255);
	evo_raster_polygon(im, bx, by, 4, OBSTACLE_EDGE, 255);
}

static void draw_zone(evo_raster *im, const evo_view_camera *cam,
		      const evo_element *z)
{
	double bx[4], by[4];
	box_corners(cam, z->x, z->y, z->angle, z->size, z->size, bx, by);
	if (!z->active) {
		evo_raster_polygon(im, bx, by, 4, ZONE_OFF, 255);
		return;
	}
	evo_raster_fill_polygon(im, bx, by, 4, EVO_VIEW_ZONE,
				EVO_VIEW_ZONE_ALPHA);
	evo_raster_polygon(im, bx, by, 4, ZONE_EDGE, 255);
}

static void draw_object(evo_raster *im, const evo_view_camera *cam,
			const evo_scene *sc, const evo_element *o)
{
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
	evo_raster_fill_circle(im, sx, sy, r, EVO_VIEW_OBJECT, 255);
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
	evo_raster_fill_circle(im, sx, sy, r, evo_view_team_colour(bot->team),
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
		if (a->def.kind != EVO_ACTUATOR_CLAW)
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

/* ---- the panel ------------------------------------------------------- */

#define PANEL_DIM   0x9AA0A8u
#define BAR_BACK    0x3A3F47u
#define PAUSED_TEXT 0xFFC23Du

/* Draw s clipped to `chars` characters (the last one a '~' when cut). */
static void text_fit(evo_raster *im, int x, int y, const char *s, int chars,
		     uint32_t rgb, int scale)
{
	char buf[128];
	if (chars < 1)
		return;
	if (chars > (int)sizeof buf - 1)
		chars = (int)sizeof buf - 1;
	snprintf(buf, sizeof buf, "%s", s);
	for (char *c = buf; *c; c++)
		if (*c == '\n')
			*c = ' ';
	if ((int)strlen(buf) > chars) {
		buf[chars - 1] = '~';
		buf[chars] = 0;
	}
	evo_raster_text(im, x, y, buf, rgb, scale);
}

/* The panel's title, the task's path, in `chars` characters: whole when
 * it fits, else its file name (the part that tells tasks apart), else
 * that name's end after a '~'. Cutting the path's end, as text_fit does,
 * left "minds/Avoid/Tasks/A~" of every Avoid task. */
static void title_fit(evo_raster *im, int x, int y, const char *title,
		      int chars, int scale)
{
	char name[128];
	const char *s = title ? title : "evo";
	const char *slash = strrchr(s, '/');
	if ((int)strlen(s) > chars && slash && slash[1])
		s = slash + 1;
	snprintf(name, sizeof name, "%s", s);
	char *dot = strrchr(name, '.');
	if ((int)strlen(name) > chars && dot && dot != name)
		*dot = 0; /* MediumMaze-DEMO, without .simbatch */
	int n = (int)strlen(name);
	if (n > chars && chars > 1) {
		char buf[128];
		if (chars > (int)sizeof buf - 1)
			chars = (int)sizeof buf - 1;
		snprintf(buf, sizeof buf, "~%s", name + n - (chars - 1));
		evo_raster_text(im, x, y, buf, EVO_VIEW_TEXT, scale);
		return;
	}
	text_fit(im, x, y, name, chars, EVO_VIEW_TEXT, scale);
}

#define NEUTRAL_MARK 0xE8E8E8u

/* One column of named bars from (x, y), w wide, down to y_end: a title,
 * then a row per value (name, bar, value), rows closer when they would not
 * fit, and the rest left out with a note of how many. Returns the y
 * below the last row. */
static int draw_bars(evo_raster *im, int x, int y, int w, int y_end,
		     const char *title, int n, const char *const *names,
		     const double *values, uint32_t colour, int neutral)
{
	char line[64];
	snprintf(line, sizeof line, "%s (%d)", title, n);
	text_fit(im, x, y, line, w / EVO_FONT_CELL_W, PANEL_DIM, 1);
	y += EVO_FONT_CELL_H + 6;
	int row = 16, bar_h = 9;
	if (n * row > y_end - y) {
		row = EVO_FONT_CELL_H + 2;
		bar_h = EVO_FONT_H;
	}
	int name_chars = 8, value_w = 5 * EVO_FONT_CELL_W;
	int bar_x = x + name_chars * EVO_FONT_CELL_W + 6;
	int bar_w = x + w - value_w - 4 - bar_x;
	for (int k = 0; k < n; k++, y += row) {
		if (y + row > y_end) {
			snprintf(line, sizeof line, "... %d more", n - k);
			text_fit(im, x, y, line, w / EVO_FONT_CELL_W, PANEL_DIM,
				 1);
			return y + row;
		}
		double v = values ? values[k] : 0;
		v = v > 1 ? 1 : v > 0 ? v : 0; /* NaN: 0 */
		const char *name = names && names[k] ? names[k] : "?";
		text_fit(im, x, y, name, name_chars, EVO_VIEW_TEXT, 1);
		if (bar_w < 4)
			continue;
		evo_raster_fill_rect(im, bar_x, y, bar_w, bar_h, BAR_BACK, 255);
		evo_raster_fill_rect(im, bar_x, y, (int)lround(v * bar_w),
				     bar_h, colour, 255);
		if (neutral)
			evo_raster_fill_rect(im, bar_x + bar_w / 2, y - 1, 1,
					     bar_h + 2, NEUTRAL_MARK, 255);
		snprintf(line, sizeof line, "%.3f", v);
		evo_raster_text(im, x + w - value_w, y, line, PANEL_DIM, 1);
	}
	return y;
}

/* The teams, each a swatch of its colour, its name and its reward. */
static int draw_teams(evo_raster *im, int x, int y, int w,
		      const evo_viewer_panel *p)
{
	char line[96];
	text_fit(im, x, y, "teams", w / EVO_FONT_CELL_W, PANEL_DIM, 1);
	y += EVO_FONT_CELL_H + 4;
	for (int k = 0; k < p->n_teams; k++) {
		evo_raster_fill_rect(im, x, y, 9, 9, evo_view_team_colour(k),
				     255);
		snprintf(line, sizeof line, "%s %.6g",
			 p->team_name && p->team_name[k] ? p->team_name[k]
							 : "?",
			 p->team_reward ? p->team_reward[k] : 0.0);
		text_fit(im, x + 14, y, line, (w - 14) / EVO_FONT_CELL_W,
			 EVO_VIEW_TEXT, 1);
		y += EVO_FONT_CELL_H + 3;
	}
	return y + 4;
}

/* The selected bot: its name and team, reward, then its sensors and
 * actuators as bars. */
static int draw_selected(evo_raster *im, int x, int y, int w, int y_end,
			 const evo_viewer_panel *p)
{
	char line[128];
	snprintf(line, sizeof line, "%s%s%s%s", p->bot_name,
		 p->bot_team ? " (" : "", p->bot_team ? p->bot_team : "",
		 p->bot_team ? ")" : "");
	text_fit(im, x, y, line, w / EVO_FONT_CELL_W, EVO_VIEW_SELECTED, 1);
	y += EVO_FONT_CELL_H + 3;
	snprintf(line, sizeof line, "reward %.6g  camera %s", p->bot_reward,
		 p->following ? "follows" : "free");
	text_fit(im, x, y, line, w / EVO_FONT_CELL_W, EVO_VIEW_TEXT, 1);
	y += EVO_FONT_CELL_H + 6;
	/* sensors get two thirds of the room, actuators the rest */
	int room = y_end - y;
	y = draw_bars(im, x, y, w, y + room * 2 / 3, "sensors", p->n_sensors,
		      p->sensor_name, p->sensor, EVO_VIEW_SENSOR_BAR, 0);
	y = draw_bars(im, x, y + 4, w, y_end, "actuators", p->n_actuators,
		      p->actuator_name, p->actuator, EVO_VIEW_ACTUATOR_BAR, 1);
	return y + 4;
}

static void panel_at(evo_raster *im, int x0, const evo_scene *sc,
		     const evo_viewer_panel *p);

static void draw_panel(evo_raster *im, const evo_scene *sc,
		       const evo_view_camera *cam, const evo_viewer_panel *p)
{
	panel_at(im, cam->world_w, sc, p);
}

void evo_view_render_panel(evo_raster *im, int x0, const evo_viewer_panel *p)
{
	panel_at(im, x0, NULL, p);
}

/* The panel from column x0; sc gives the figures when p is NULL (one of
 * the two is not). */
static void panel_at(evo_raster *im, int x0, const evo_scene *sc,
		     const evo_viewer_panel *p)
{
	int w = im->w - x0;
	if (w < 40)
		return;
	evo_raster_fill_rect(im, x0, 0, w, im->h, EVO_VIEW_PANEL, 255);
	int scale = w >= 200 ? 2 : 1;
	int cw = EVO_FONT_CELL_W * scale, lh = EVO_FONT_CELL_H * scale + 4;
	int x = x0 + 12, y = 12, chars = (w - 24) / cw;
	char line[128];

	title_fit(im, x, y, p ? p->title : NULL, chars, scale);
	y += lh + 6;
	long tick = p ? p->tick : sc->tick;
	snprintf(line, sizeof line, "tick    %ld", tick);
	text_fit(im, x, y, line, chars, EVO_VIEW_TEXT, scale);
	y += lh;
	if (p) {
		snprintf(line, sizeof line, "episode %d", p->episode);
		text_fit(im, x, y, line, chars, EVO_VIEW_TEXT, scale);
		y += lh;
	}
	snprintf(line, sizeof line, "step    %.4g",
		 p ? p->step_reward : sc->step_reward);
	text_fit(im, x, y, line, chars, EVO_VIEW_TEXT, scale);
	y += lh;
	snprintf(line, sizeof line, "total   %.6g",
		 p ? p->episode_reward : sc->episode_reward);
	text_fit(im, x, y, line, chars, EVO_VIEW_TEXT, scale);
	y += lh;
	if (p && p->speed > 0) {
		snprintf(line, sizeof line, "speed   %gx", p->speed);
		text_fit(im, x, y, line, chars, EVO_VIEW_TEXT, scale);
		y += lh;
	}
	if (p && p->paused) {
		text_fit(im, x, y, "PAUSED", chars, PAUSED_TEXT, scale);
		y += lh;
	}

	/* The key help takes the bottom; skills get what is between. */
	static const char *const help2d[] = {
	    "space pause   n step", "up/down speed r reset",
	    "+/- zoom      s shot", "click/tab bot c camera", "q quit"};
	const char *const *help = p && p->help ? p->help : help2d;
	int n_help = p && p->help ? p->n_help : 5;
	int help_h = n_help * EVO_FONT_CELL_H + 8;
	if (p && p->n_teams > 0)
		y = draw_teams(im, x, y + 6, w - 24, p);
	if (p && p->bot_name) {
		/* the skills keep at least a third of what is left */
		int n_sk = p->influence ? p->n_influence : 0;
		int skills_h = n_sk * (EVO_FONT_CELL_H + 4) + lh + 10;
		int left = im->h - help_h - y;
		if (skills_h > left / 3)
			skills_h = left / 3;
		y = draw_selected(im, x, y + 6, w - 24,
				  im->h - help_h - skills_h, p);
	}
	int n = p && p->influence ? p->n_influence : 0;
	if (n > 0) {
		y += 10;
		text_fit(im, x, y, "skills", chars, PANEL_DIM, scale);
		y += lh;
		int room = im->h - help_h - y;
		/* A skill takes a name line and a bar; when they do not
		 * fit, small names with the bar beside them. */
		int row = lh + 14, compact = n * row > room;
		if (compact)
			row = EVO_FONT_CELL_H + 4;
		for (int k = 0; k < n && y + row <= im->h - help_h; k++) {
			double v = p->influence[k];
			v = v > 1 ? 1 : v > 0 ? v : 0; /* NaN: 0 */
			const char *name =
			    p->influence_name && p->influence_name[k]
				? p->influence_name[k]
				: "?";
			int bar_x = x, bar_y = y + lh, bar_w = w - 24,
			    bar_h = 9;
			if (compact) {
				int name_chars = (w - 24) / 2 / EVO_FONT_CELL_W;
				text_fit(im, x, y, name, name_chars,
					 EVO_VIEW_TEXT, 1);
				bar_x = x + name_chars * EVO_FONT_CELL_W + 4;
				bar_w = x0 + w - 12 - bar_x;
				bar_y = y;
				bar_h = EVO_FONT_H;
			} else {
				snprintf(line, sizeof line, "%.2f", v);
				int vw = evo_raster_text_width(line, scale);
				text_fit(im, x, y, name, chars - 5,
					 EVO_VIEW_TEXT, scale);
				evo_raster_text(im, x0 + w - 12 - vw, y, line,
						PANEL_DIM, scale);
			}
			evo_raster_fill_rect(im, bar_x, bar_y, bar_w, bar_h,
					     BAR_BACK, 255);
			evo_raster_fill_rect(im, bar_x, bar_y,
					     (int)lround(v * bar_w), bar_h,
					     EVO_VIEW_BAR, 255);
			y += row;
		}
	}
	y = im->h - help_h + 4;
	for (int k = 0; k < n_help; k++, y += EVO_FONT_CELL_H)
		text_fit(im, x, y, help[k], (w - 24) / EVO_FONT_CELL_W,
			 PANEL_DIM, 1);
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
	for (int e = 0; e < sc->n_elements; e++)
		if (sc->element[e].kind == EVO_ELEM_ZONE)
			draw_zone(im, cam, &sc->element[e]);
	for (int o = 0; o < sc->n_obstacles; o++)
		draw_obstacle(im, cam, &sc->obstacle[o]);
	for (int e = 0; e < sc->n_elements; e++)
		if (sc->element[e].kind == EVO_ELEM_OBJECT &&
		    sc->element[e].held_by < 0)
			draw_object(im, cam, sc, &sc->element[e]);
	draw_trail(im, cam, p);
	for (int b = 0; b < sc->n_bots; b++)
		draw_bot(im, cam, sc, b);
	/* Rays over the bots: a sensor placed inside the body still shows
	 * its whole fan. An idle sensor (nothing reads it) is not sampled,
	 * so it has no rays to show. */
	for (int b = 0; b < sc->n_bots; b++)
		for (int s = 0; s < sc->bot[b].n_sensors; s++)
			if (sc->bot[b].sensor[s].def.kind ==
				    EVO_SENSOR_PROXIMITY &&
			    !sc->bot[b].sensor[s].idle)
				draw_rays(im, cam, sc, b,
					  &sc->bot[b].sensor[s]);
	/* Held objects over the bot that carries them. */
	for (int e = 0; e < sc->n_elements; e++)
		if (sc->element[e].kind == EVO_ELEM_OBJECT &&
		    sc->element[e].held_by >= 0)
			draw_object(im, cam, sc, &sc->element[e]);
	for (int b = 0; b < sc->n_bots; b++)
		draw_claws(im, cam, sc, b);
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
	draw_panel(im, sc, cam, p);
}

/* ---- a remote robot's frame ------------------------------------------- */

#define NEUTRAL_MARK 0xE8E8E8u

void evo_view_render_remote(evo_raster *im, const evo_view_remote *p)
{
	static const evo_view_remote none = {0};
	if (!p)
		p = &none;
	evo_raster_clear(im, EVO_VIEW_PANEL);
	int scale = im->w >= 480 ? 2 : 1;
	int lh = EVO_FONT_CELL_H * scale + 4, x = 12, y = 12;
	int chars = (im->w - 24) / (EVO_FONT_CELL_W * scale);
	char line[160];
	title_fit(im, x, y, p->title, chars, scale);
	y += lh + 4;

	/* the link: a coloured box with its state, then the robot */
	uint32_t colour = EVO_VIEW_LINK_IDLE;
	switch (p->link) {
	case EVO_VIEW_LINK_LIVE:
		colour = EVO_VIEW_LINK_OK;
		snprintf(line, sizeof line, "LIVE");
		break;
	case EVO_VIEW_LINK_QUIET:
		colour = EVO_VIEW_LINK_WARN;
		snprintf(line, sizeof line, "QUIET %.1f s", p->quiet);
		break;
	case EVO_VIEW_LINK_SILENT:
		colour = EVO_VIEW_LINK_BAD;
		snprintf(line, sizeof line, "SILENT %.1f s", p->quiet);
		break;
	case EVO_VIEW_LINK_ENDED:
		snprintf(line, sizeof line, "ENDED");
		break;
	default:
		snprintf(line, sizeof line, "WAITING");
		break;
	}
	int bw = evo_raster_text_width(line, scale) + 16;
	evo_raster_fill_rect(im, x, y - 4, bw, lh + 2, colour, 255);
	evo_raster_text(im, x + 8, y, line, EVO_VIEW_PANEL, scale);
	snprintf(line, sizeof line, "robot %s, a tick every %.1f ms",
		 p->remote ? p->remote : "?", p->period_ms);
	int rest = (im->w - x - bw - 24) / (EVO_FONT_CELL_W * scale);
	text_fit(im, x + bw + 12, y, line, rest, EVO_VIEW_TEXT, scale);
	y += lh + 6;
	snprintf(line, sizeof line, "episode %d   tick %ld   reward %.6g",
		 p->episode, p->tick, p->reward);
	text_fit(im, x, y, line, chars, EVO_VIEW_TEXT, scale);
	y += lh;
	snprintf(line, sizeof line, "in time %lu   late %lu   missing %lu",
		 p->in_time, p->late, p->missing);
	text_fit(im, x, y, line, chars,
		 p->late || p->missing ? PAUSED_TEXT : EVO_VIEW_TEXT, scale);
	y += lh + 10;

	/* three columns, the help at the bottom */
	int help_h = EVO_FONT_CELL_H + 8, gap = 16;
	int col_w = (im->w - 24 - 2 * gap) / 3;
	int y_end = im->h - help_h;
	if (col_w >= 40) {
		draw_bars(im, x, y, col_w, y_end, "sensors", p->n_sensors,
			  p->sensor_name, p->sensor, EVO_VIEW_SENSOR_BAR, 0);
		draw_bars(im, x + col_w + gap, y, col_w, y_end, "actuators",
			  p->n_actuators, p->actuator_name, p->actuator,
			  EVO_VIEW_ACTUATOR_BAR, 1);
		draw_bars(im, x + 2 * (col_w + gap), y, col_w, y_end,
			  "skills", p->n_influence, p->influence_name,
			  p->influence, EVO_VIEW_BAR, 0);
	}
	text_fit(im, x, im->h - help_h + 4, "q quit   s screenshot",
		 (im->w - 24) / EVO_FONT_CELL_W, PANEL_DIM, 1);
}

/* ---- the window ------------------------------------------------------ */

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

evo_viewer *evo_viewer_open(int width, int height, evo_err *err)
{
	if (width <= 0 || height <= 0) {
		width = 1024;
		height = 720;
	}
	if (evo_sdl_load(0, "the viewer", err))
		return NULL;
	/* Left alone, SDL backs the window of a software renderer with a
	 * GL texture, loading Mesa (llvmpipe under Xvfb) for each window
	 * only to copy a bitmap. Plain X11 (XShm) images are enough; at
	 * default priority, so SDL_FRAMEBUFFER_ACCELERATION in the
	 * environment still wins. */
	SDL_SetHintWithPriority(SDL_HINT_FRAMEBUFFER_ACCELERATION, "0",
				SDL_HINT_DEFAULT);
	if (SDL_InitSubSystem(SDL_INIT_VIDEO) != 0) {
		evo_fail(err,
			 "cannot open the viewer: %s (no display? set "
			 "DISPLAY, or run with --headless)",
			 SDL_GetError());
		return NULL;
	}
	evo_viewer *v = calloc(1, sizeof *v);
	if (!v) {
		evo_fail(err, "cannot open the viewer: out of memory");
		SDL_QuitSubSystem(SDL_INIT_VIDEO);
		return NULL;
	}
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
		if (ev.type == SDL_QUIT)
			return EVO_VIEW_QUIT;
		if (ev.type == SDL_WINDOWEVENT &&
		    ev.window.event == SDL_WINDOWEVENT_CLOSE)
			return EVO_VIEW_QUIT;
		if (ev.type == SDL_MOUSEWHEEL) {
			evo_viewer_zoom(v, ev.wheel.y > 0   ? 1.25
					   : ev.wheel.y < 0 ? 0.8
							    : 1);
			continue;
		}
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
		if (ev.type != SDL_KEYDOWN)
			continue;
		evo_view_action a =
		    evo_view_key(ev.key.keysym.sym, ev.key.repeat);
		if (a != EVO_VIEW_NONE)
			return a;
		switch (ev.key.keysym.sym) {
		case SDLK_TAB:
			return EVO_VIEW_NEXT_BOT;
		case SDLK_PLUS:
		case SDLK_EQUALS:
		case SDLK_KP_PLUS:
			evo_viewer_zoom(v, 1.25);
			break;
		case SDLK_MINUS:
		case SDLK_KP_MINUS:
			evo_viewer_zoom(v, 0.8);
			break;
		case SDLK_0:
		case SDLK_KP_0:
			v->zoom = 1;
			break;
		default:
			break;
		}
	}
	return EVO_VIEW_NONE;
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
