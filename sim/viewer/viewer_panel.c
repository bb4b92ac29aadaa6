/* The viewer's panel (sim/viewer/viewer.h): the selected bot's sensors
 * and actuators as bars, the teams' scores, the pause and speed line, and
 * DEMOREMOTE's frame of a remote robot (evo_view_render_remote). */
#include "viewer/viewer.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "viewer/viewer_internal.h"
#include "world2d/query.h"

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
		     const char *title, const evo_view_bars *bars,
		     uint32_t colour, int neutral)
{
	int n = bars->n;
	const char *const *names = bars->name;
	const double *values = bars->value;
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
	y = draw_bars(im, x, y, w, y + room * 2 / 3, "sensors", &p->sensors,
		      EVO_VIEW_SENSOR_BAR, 0);
	y = draw_bars(im, x, y + 4, w, y_end, "actuators", &p->actuators,
		      EVO_VIEW_ACTUATOR_BAR, 1);
	return y + 4;
}

static void panel_at(evo_raster *im, int x0, const evo_scene *sc,
		     const evo_viewer_panel *p);

void view_draw_panel(evo_raster *im, const evo_scene *sc,
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
		int n_sk = p->influence.value ? p->influence.n : 0;
		int skills_h = n_sk * (EVO_FONT_CELL_H + 4) + lh + 10;
		int left = im->h - help_h - y;
		if (skills_h > left / 3)
			skills_h = left / 3;
		y = draw_selected(im, x, y + 6, w - 24,
				  im->h - help_h - skills_h, p);
	}
	int n = p && p->influence.value ? p->influence.n : 0;
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
			double v = p->influence.value[k];
			v = v > 1 ? 1 : v > 0 ? v : 0; /* NaN: 0 */
			const char *name =
			    p->influence.name && p->influence.name[k]
				? p->influence.name[k]
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
		draw_bars(im, x, y, col_w, y_end, "sensors", &p->sensors,
			  EVO_VIEW_SENSOR_BAR, 0);
		draw_bars(im, x + col_w + gap, y, col_w, y_end, "actuators",
			  &p->actuators, EVO_VIEW_ACTUATOR_BAR, 1);
		draw_bars(im, x + 2 * (col_w + gap), y, col_w, y_end,
			  "skills", &p->influence, EVO_VIEW_BAR, 0);
	}
	text_fit(im, x, im->h - help_h + 4, "q quit   s screenshot",
		 (im->w - 24) / EVO_FONT_CELL_W, PANEL_DIM, 1);
}