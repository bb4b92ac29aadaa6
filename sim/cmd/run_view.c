/* `evo run` of a 2D task in the viewer, or its frames drawn off screen
 * (cmd/run_internal.h): the pacing, the panel, the bot's trail, the
 * camera of --camera and --zoom, --record and a --screenshot without a
 * window, and the window's loop with its playback keys. */
#define _POSIX_C_SOURCE 200809L
#include "cmd/run_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/clock.h"
#include "cmd/record.h"

static void sleep_until(double t)
{
	double d = t - evo_clock_now();
	if (d <= 0)
		return;
	struct timespec ts = {(time_t)d, (long)((d - (double)(time_t)d) * 1e9)};
	nanosleep(&ts, NULL);
}

void evo_run_pace(double *next, double speed)
{
	*next += 1.0 / (30.0 * speed);
	if (*next < evo_clock_now() - 0.5)
		*next = evo_clock_now();
	sleep_until(*next);
}

/* What the viewer shows of whom: the bot selected (-1: none) and whether
 * the camera follows it. A one-agent task follows its bot and selects
 * none until a click; a team task selects its first bot, camera free. */
typedef struct view_state {
	int selected;
	int follow;
} view_state;

static view_state view_start(const evo_sim *s)
{
	view_state vs = {-1, 1};
	if (s->has_teams) {
		vs.selected = s->agent[0].bot;
		vs.follow = 0;
	}
	return vs;
}

/* The bot the camera follows: the selected one, or the one agent's;
 * -1 for the free camera. */
static int view_follow(const evo_sim *s, const view_state *vs)
{
	if (!vs->follow)
		return -1;
	return vs->selected >= 0 ? vs->selected : s->bot;
}

/* The selected bot's part of the panel: its names and values. */
static void panel_bot(panel_data *pd, evo_viewer_panel *p, const evo_sim *s,
		      int bot)
{
	const evo_bot *b = &s->scene->bot[bot];
	int a = evo_sim_agent_of_bot(s, bot);
	p->bot_name = b->name;
	p->bot = bot;
	p->bot_team = b->team >= 0 && b->team < s->n_teams && s->has_teams
			  ? s->team[b->team].name
			  : NULL;
	p->bot_reward = b->reward;
	if (a < 0) {
		/* no mind: every sensor and actuator of the bot */
		int ns = b->n_sensors < EVO_MAX_SENSORS ? b->n_sensors
							: EVO_MAX_SENSORS;
		int na = b->n_actuators < EVO_MAX_ACTUATORS ? b->n_actuators
							    : EVO_MAX_ACTUATORS;
		for (int i = 0; i < ns; i++) {
			pd->sensor_name[i] = b->sensor[i].name;
			pd->sensor[i] = b->sensor[i].value;
		}
		for (int i = 0; i < na; i++) {
			pd->actuator_name[i] = b->actuator[i].name;
			pd->actuator[i] = b->actuator[i].command;
		}
		p->sensors.n = ns;
		p->actuators.n = na;
		p->influence.n = 0;
	} else {
		/* what its mind reads and writes, in botdesc order */
		const evo_sim_agent *ag = &s->agent[a];
		const evo_sim_team *tm = &s->team[ag->team];
		const evo_mind *m = &ag->mind->mind;
		for (unsigned i = 0; i < m->n_sensors; i++) {
			pd->sensor_name[i] = evo_mind_sensor_name(m, i);
			pd->sensor[i] = b->sensor[tm->sensor_map[i]].value;
		}
		for (unsigned i = 0; i < m->n_actuators; i++) {
			pd->actuator_name[i] = evo_mind_actuator_name(m, i);
			pd->actuator[i] =
			    b->actuator[tm->actuator_map[i]].command;
		}
		p->sensors.n = (int)m->n_sensors;
		p->actuators.n = (int)m->n_actuators;
		int n = m->n_skills < 256 ? (int)m->n_skills : 256;
		for (int i = 0; i < n; i++) {
			pd->names[i] = evo_mind_skill_name(m, (unsigned)i);
			pd->infl[i] =
			    evo_q16_to_double(ag->state->influence[i]);
		}
		p->influence.n = n;
	}
	p->sensors.name = pd->sensor_name;
	p->sensors.value = pd->sensor;
	p->actuators.name = pd->actuator_name;
	p->actuators.value = pd->actuator;
}

static evo_viewer_panel panel_for(panel_data *pd, const evo_sim *s, long e,
				  const char *title, const view_state *vs)
{
	const evo_mind *m = &s->mind->mind;
	int n = m->n_skills < 256 ? (int)m->n_skills : 256;
	for (int i = 0; i < n; i++) {
		pd->names[i] = evo_mind_skill_name(m, (unsigned)i);
		pd->infl[i] = evo_q16_to_double(s->state->influence[i]);
	}
	evo_viewer_panel p = {
	    .tick = s->scene->tick,
	    .episode = (int)e,
	    .step_reward = s->scene->step_reward,
	    .episode_reward = s->scene->episode_reward,
	    .influence.n = n,
	    .influence.name = pd->names,
	    .influence.value = pd->infl,
	    .title = title,
	    .following = vs->follow,
	};
	if (s->has_teams) {
		for (int k = 0; k < s->n_teams; k++)
			pd->team_name[k] = s->team[k].name;
		p.n_teams = s->n_teams;
		p.team_name = pd->team_name;
		p.team_reward = s->scene->team_reward;
	}
	if (vs->selected >= 0 && vs->selected < s->scene->n_bots)
		panel_bot(pd, &p, s, vs->selected);
	return p;
}

/* --trail: the path of the task's bot this episode, for the viewer to
 * draw. A trail that cannot grow (out of memory) stops growing. */
typedef struct trail {
	double *x, *y;
	int n, cap;
} trail;

static void trail_add(trail *tr, const evo_sim *s)
{
	if (s->scene3d || s->bot < 0 || s->bot >= s->scene->n_bots)
		return;
	if (tr->n == tr->cap) {
		int cap = tr->cap ? 2 * tr->cap : 1024;
		double *x = realloc(tr->x, (size_t)cap * sizeof *x);
		if (x)
			tr->x = x;
		double *y = x ? realloc(tr->y, (size_t)cap * sizeof *y) : NULL;
		if (!y)
			return;
		tr->y = y;
		tr->cap = cap;
	}
	tr->x[tr->n] = s->scene->bot[s->bot].x;
	tr->y[tr->n] = s->scene->bot[s->bot].y;
	tr->n++;
}

/* A new episode's trail: where the bot starts. */
static void trail_restart(trail *tr, const run_opts *o, const evo_sim *s)
{
	tr->n = 0;
	if (o->trail)
		trail_add(tr, s);
}

static void trail_show(const trail *tr, evo_viewer_panel *p)
{
	p->n_trail = tr->n;
	p->trail_x = tr->x;
	p->trail_y = tr->y;
}

static void trail_free(trail *tr)
{
	free(tr->x);
	free(tr->y);
	*tr = (trail){0};
}

/* The camera of a frame drawn off screen: --camera and --zoom over the
 * viewer's own choice. */
static evo_view_camera frame_camera(const evo_sim *s, const run_opts *o,
				    const view_state *vs)
{
	/* the scene as it starts, unless --camera bot: a picture of the
	 * world, not of the bot's surroundings, all of it when no --zoom
	 * says otherwise (a maze wider than zoom 1's 60 m) */
	int follow = o->camera == 3 ? view_follow(s, vs) : EVO_VIEW_SCENE_START;
	double zoom = o->zoom > 0 ? o->zoom : 1.0;
	if (!(o->zoom > 0) && (o->camera == 0 || o->camera == 1))
		zoom = evo_view_fit_zoom(s->scene, VIEW_W, VIEW_H);
	evo_view_camera cam =
	    evo_view_camera_for(s->scene, follow, zoom, VIEW_W, VIEW_H);
	if (o->camera == 2) {
		cam.x = o->camera_x;
		cam.y = o->camera_y;
	}
	return cam;
}

/* Draw the frame the viewer would show into im, with the bot's path
 * (--trail); a 3D task's in v3, the 3D view off screen, as its window
 * shows it (the camera following the robot). */
static void draw_frame(evo_raster *im, evo_sim *s, const run_opts *o, long e,
		       const trail *tr, evo_view3d *v3)
{
	static panel_data pd;
	if (s->scene3d) {
		evo_viewer_panel p = evo_run_panel3d(&pd, s, e, o->task, 1);
		p.speed = 1.0;
		evo_view3d_draw(v3, s->scene3d, 0, &p);
		evo_view3d_frame(v3, im);
		return;
	}
	view_state vs = view_start(s);
	evo_viewer_panel p = panel_for(&pd, s, e, o->task, &vs);
	trail_show(tr, &p);
	evo_view_camera cam = frame_camera(s, o, &vs);
	evo_view_render(im, s->scene, &cam, &p);
}

/* --record: the run's episodes drawn off screen, a frame at each
 * episode's start and every --record-every ticks, into a folder of PNG
 * files or a video. */
int evo_run_record_frames(evo_sim *s, const run_opts *o, uint64_t seed,
			  evo_view3d *v3, evo_err *err)
{
	long every = o->record_every > 0 ? o->record_every : 1;
	evo_raster im;
	if (evo_raster_init(&im, VIEW_W, VIEW_H, err))
		return -1;
	evo_recorder *rec = evo_record_open(o->record, VIEW_W, VIEW_H, 30, err);
	int rc = rec ? 0 : -1;
	trail tr = {0};
	for (long e = 1; rc == 0 && e <= o->episodes && !evo_cmd_stop_requested;
	     e++) {
		if (evo_sim_reset(s, (int)e, evo_run_grid_seed(seed, e),
				  evo_run_episode_seed(seed, e), err)) {
			rc = -1;
			break;
		}
		trail_restart(&tr, o, s);
		draw_frame(&im, s, o, e, &tr, v3);
		rc = evo_record_frame(rec, &im, err);
		long t = 0;
		while (rc == 0 && !evo_cmd_stop_requested &&
		       (o->ticks == 0 || t < o->ticks)) {
			int r = evo_sim_tick(s, err);
			if (r < 0)
				rc = -1;
			t++;
			if (o->trail)
				trail_add(&tr, s);
			if (rc == 0 && (t % every == 0 || r > 0)) {
				draw_frame(&im, s, o, e, &tr, v3);
				rc = evo_record_frame(rec, &im, err);
			}
			if (r > 0)
				break;
		}
		if (rc == 0 && evo_run_print_episode(s, e, t, err))
			rc = -1;
	}
	long frames = 0;
	evo_err cerr = {{0}};
	if (evo_record_close(rec, &frames, &cerr) && rc == 0) {
		*err = cerr;
		rc = -1;
	}
	if (rc == 0)
		printf("recorded %ld frame%s in %s\n", frames,
		       frames == 1 ? "" : "s", o->record);
	evo_raster_free(&im);
	trail_free(&tr);
	return rc;
}

/* --screenshot without a window: episode 1 for --ticks ticks (without
 * them and TICKLIM, until the episode ends, as a headless run), then the
 * frame the viewer would show at its default size, drawn off screen, and
 * the episode's line. */
int evo_run_screenshot_headless(evo_sim *s, const run_opts *o, uint64_t seed,
				evo_view3d *v3, evo_err *err)
{
	if (evo_sim_reset(s, 1, evo_run_grid_seed(seed, 1),
			  evo_run_episode_seed(seed, 1), err))
		return -1;
	if (v3)
		evo_view3d_aim(v3, s->scene3d);
	trail tr = {0};
	trail_restart(&tr, o, s);
	long t = 0;
	while ((o->ticks == 0 || t < o->ticks) && !evo_cmd_stop_requested) {
		int r = evo_sim_tick(s, err);
		if (r < 0) {
			trail_free(&tr);
			return -1;
		}
		t++;
		if (o->trail)
			trail_add(&tr, s);
		if (r > 0)
			break;
	}
	evo_raster im;
	if (evo_raster_init(&im, VIEW_W, VIEW_H, err)) {
		trail_free(&tr);
		return -1;
	}
	draw_frame(&im, s, o, 1, &tr, v3);
	int rc = evo_raster_save_png(&im, o->screenshot, err);
	evo_raster_free(&im);
	trail_free(&tr);
	if (rc == 0)
		printf("saved %s (tick %ld, drawn without a window)\n",
		       o->screenshot,
		       s->core->tick);
	if (rc == 0 && evo_run_print_episode(s, 1, t, err))
		return -1;
	return rc;
}

/* The playback actions both views share: pause, one step, faster,
 * slower (1/16 to 64 times real time), the episode again (*t = -1).
 * 1 when a was one of them. */
int evo_run_playback(evo_view_action a, int *paused, int *steps, double *speed,
		     long *t)
{
	if (a == EVO_VIEW_PAUSE)
		*paused = !*paused;
	else if (a == EVO_VIEW_STEP)
		*steps = 1, *paused = 1;
	else if (a == EVO_VIEW_FASTER)
		*speed = *speed < 64 ? *speed * 2 : *speed;
	else if (a == EVO_VIEW_SLOWER)
		*speed = *speed > 1.0 / 16 ? *speed / 2 : *speed;
	else if (a == EVO_VIEW_RESET)
		*t = -1;
	else
		return 0;
	return 1;
}

int evo_run_steps(evo_sim *s, const run_opts *o, int steps, long e, long *t,
		  void (*after_tick)(void *ctx, const evo_sim *s), void *ctx,
		  evo_err *err)
{
	for (int k = 0; k < steps; k++) {
		int r = evo_sim_tick(s, err);
		if (r < 0)
			return -1;
		if (after_tick)
			after_tick(ctx, s);
		++*t;
		if (r > 0 || (o->ticks && *t >= o->ticks && !o->screenshot))
			return evo_run_print_episode(s, e, *t, err) ? -1 : 1;
	}
	return 0;
}

/* evo_run_steps' after_tick for --trail: the bot's path grows. */
static void trail_tick(void *tr, const evo_sim *s)
{
	trail_add(tr, s);
}

const char *evo_run_shot_path(long tick)
{
	static char path[64];
	snprintf(path, sizeof path, "evo-screenshot-%ld.png", tick);
	return path;
}

void evo_run_shot_said(int rc, const char *path, evo_err *err)
{
	if (rc)
		fprintf(stderr, "%s\n", err->msg);
	else
		printf("saved %s\n", path);
	err->msg[0] = 0;
}

static int run_viewer_trail(evo_sim *s, evo_viewer *v, const run_opts *o,
			    uint64_t seed, trail *tr, evo_err *err);

/* DEMOSIM in a window: real time (30 ticks a second) times the speed,
 * with pause, single step, speed and reset keys. */
int evo_run_viewer(evo_sim *s, evo_viewer *v, const run_opts *o, uint64_t seed,
		   evo_err *err)
{
	trail tr = {0};
	int rc = run_viewer_trail(s, v, o, seed, &tr, err);
	trail_free(&tr);
	return rc;
}

static int run_viewer_trail(evo_sim *s, evo_viewer *v, const run_opts *o,
			    uint64_t seed, trail *tr, evo_err *err)
{
	static panel_data pd;
	view_state vs = view_start(s);
	long e = 1, t = 0;
	if (evo_sim_reset(s, 1, evo_run_grid_seed(seed, 1),
			  evo_run_episode_seed(seed, 1), err))
		return -1;
	trail_restart(tr, o, s);
	/* a small arena starts zoomed in, as its screenshot is */
	double fit = evo_view_fit_zoom(s->scene, VIEW_W, VIEW_H);
	if (fit > 1)
		evo_viewer_zoom(v, fit);
	double speed = 1.0, next = evo_clock_now();
	int paused = 0;
	for (;;) {
		if (evo_cmd_stop_requested)
			return 0;
		int steps = paused ? 0 : 1;
		evo_view_action a;
		while ((a = evo_viewer_poll(v)) != EVO_VIEW_NONE) {
			if (a == EVO_VIEW_QUIT)
				return 0;
			if (evo_run_playback(a, &paused, &steps, &speed, &t))
				continue;
			if (a == EVO_VIEW_SELECT) {
				double x, y;
				evo_viewer_clicked(v, &x, &y);
				vs.selected = evo_view_bot_at(s->scene, x, y);
			} else if (a == EVO_VIEW_NEXT_BOT &&
				   s->scene->n_bots > 0)
				vs.selected =
				    (vs.selected + 1) % s->scene->n_bots;
			else if (a == EVO_VIEW_CAMERA)
				vs.follow = !vs.follow;
			else if (a == EVO_VIEW_FREE)
				vs.follow = 0;
			else if (a == EVO_VIEW_SCREENSHOT) {
				const char *path =
				    evo_run_shot_path(s->scene->tick);
				evo_run_shot_said(
				    evo_viewer_screenshot(v, path, err), path,
				    err);
			}
		}
		if (t < 0 || (o->episodes && e > o->episodes)) {
			if (e > o->episodes && o->episodes)
				return 0;
			t = 0;
			if (evo_sim_reset(s, (int)e, evo_run_grid_seed(seed, e),
					  evo_run_episode_seed(seed, e), err))
				return -1;
			trail_restart(tr, o, s);
		}
		int ended = evo_run_steps(s, o, steps, e, &t,
					  o->trail ? trail_tick : NULL, tr, err);
		if (ended < 0)
			return -1;
		if (ended) {
			e++;
			t = -1;
		}
		evo_viewer_panel p = panel_for(&pd, s, e, o->task, &vs);
		p.speed = speed;
		p.paused = paused;
		trail_show(tr, &p);
		evo_viewer_draw(v, s->scene, view_follow(s, &vs), &p);
		if (o->screenshot && t >= o->ticks) {
			if (evo_viewer_screenshot(v, o->screenshot, err))
				return -1;
			printf("saved %s (tick %ld)\n", o->screenshot,
			       s->scene->tick);
			return 0;
		}
		evo_run_pace(&next, speed);
	}
}
