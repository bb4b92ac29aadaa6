/* `evo run` of a DEMOREMOTE task (cmd/run_internal.h): the mind here
 * answers a robot's ticks over LCM or CAN, with the robot's frame in the
 * viewer when there is one. */
#define _POSIX_C_SOURCE 200809L
#include "cmd/run_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lua/lua_evo.h"
#include "mind/trace.h"

/* ---- DEMOREMOTE: a robot ------------------------------------------------ */

/* What the robot's frame shows (viewer.h, evo_view_remote). */
typedef struct robot_view {
	const char *sensor_name[EVO_MAX_SENSORS];
	const char *actuator_name[EVO_MAX_ACTUATORS];
	const char *skill_name[256];
	double sensor[EVO_MAX_SENSORS], actuator[EVO_MAX_ACTUATORS];
	double influence[256];
	evo_view_remote p;
} robot_view;

static void robot_view_init(robot_view *rv, const evo_mind *m,
			    const evo_robot_conn *r, const char *title)
{
	memset(rv, 0, sizeof *rv);
	for (unsigned i = 0; i < m->n_sensors; i++)
		rv->sensor_name[i] = evo_mind_sensor_name(m, i);
	for (unsigned i = 0; i < m->n_actuators; i++) {
		rv->actuator_name[i] = evo_mind_actuator_name(m, i);
		rv->actuator[i] = 0.5;
	}
	int n = m->n_skills < 256 ? (int)m->n_skills : 256;
	for (int i = 0; i < n; i++)
		rv->skill_name[i] = evo_mind_skill_name(m, (unsigned)i);
	evo_view_remote *p = &rv->p;
	p->title = title;
	p->remote = evo_robot_conn_name(r);
	p->period_ms = evo_robot_conn_period(r) * 1e3;
	p->tick = -1;
	p->sensors.n = (int)m->n_sensors;
	p->sensors.name = rv->sensor_name;
	p->sensors.value = rv->sensor;
	p->actuators.n = (int)m->n_actuators;
	p->actuators.name = rv->actuator_name;
	p->actuators.value = rv->actuator;
	p->influence.n = n;
	p->influence.name = rv->skill_name;
	p->influence.value = rv->influence;
}

/* The link's state and the counts, as they are now. */
static void robot_view_update(robot_view *rv, const evo_robot_conn *r, long e)
{
	evo_view_remote *p = &rv->p;
	evo_robot_status st;
	evo_robot_conn_status(r, &st);
	double period = evo_robot_conn_period(r);
	double timeout = evo_robot_conn_timeout(r);
	p->episode = (int)e;
	p->quiet = st.quiet;
	p->reward = st.reward;
	p->in_time = st.in_time;
	p->late = st.late;
	p->missing = st.missing;
	p->link = st.done		  ? EVO_VIEW_LINK_ENDED
		  : st.tick < 0		  ? EVO_VIEW_LINK_WAITING
		  : st.quiet >= timeout	  ? EVO_VIEW_LINK_SILENT
		  : st.quiet > 3 * period ? EVO_VIEW_LINK_QUIET
					  : EVO_VIEW_LINK_LIVE;
}

/* The robot's frame: in the window, or drawn without one into a PNG. */
static int robot_screenshot(evo_viewer *v, const robot_view *rv,
			    const char *path, evo_err *err)
{
	if (v) {
		evo_viewer_draw_remote(v, &rv->p);
		if (evo_viewer_screenshot(v, path, err))
			return -1;
		printf("saved %s (tick %ld)\n", path, rv->p.tick);
		return 0;
	}
	evo_raster im;
	if (evo_raster_init(&im, VIEW_W, VIEW_H, err))
		return -1;
	evo_view_render_remote(&im, &rv->p);
	int rc = evo_raster_save_png(&im, path, err);
	evo_raster_free(&im);
	if (rc == 0)
		printf("saved %s (tick %ld, drawn without a window)\n", path,
		       rv->p.tick);
	return rc;
}

/* The window's keys: 1 to quit. */
static int robot_keys(evo_viewer *v, const robot_view *rv, evo_err *err)
{
	evo_view_action a;
	while ((a = evo_viewer_poll(v)) != EVO_VIEW_NONE) {
		if (a == EVO_VIEW_QUIT)
			return 1;
		if (a == EVO_VIEW_SCREENSHOT) {
			char path[64];
			snprintf(path, sizeof path, "evo-screenshot-%ld.png",
				 rv->p.tick);
			if (evo_viewer_screenshot(v, path, err))
				fprintf(stderr, "%s\n", err->msg);
			else
				printf("saved %s\n", path);
			err->msg[0] = 0;
		}
	}
	return 0;
}

/* DEMOREMOTE: the mind here, the body a robot that ticks at its own rate
 * (docs/remote.md, A robot: free running), over LCM or over CAN
 * (docs/can.md). Each tick's sensors are answered at once with that
 * tick's commands; an episode runs until --ticks, the robot's end, a stop
 * or the window's closing; the robot then gets a STOP and goes neutral. */
int evo_run_robot(const evo_task *task, const run_opts *o, uint64_t seed,
		  FILE *trace, evo_viewer *v, evo_err *err)
{
	const evo_mind *m = &task->mind->mind;
	evo_state *state = NULL;
	void *mem = evo_run_mind_state(m, &state, err);
	if (!mem)
		return -1;
	evo_robot_conn_def def = {
	    .mind = task->mind,
	    .task = task->sb,
	    .task_path = o->task,
	    .can_url = o->can,
	    .stop = &evo_cmd_stop_requested,
	};
	evo_robot_conn *r = evo_robot_conn_open(&def, err);
	if (!r) {
		free(mem);
		return evo_cmd_stop_requested ? 0 : -1;
	}
	printf("%s\n", evo_robot_conn_about(r));
	fflush(stdout);
	if (trace)
		evo_trace_header(trace, task->mind);
	static robot_view rv;
	robot_view_init(&rv, m, r, o->task);
	double period = evo_robot_conn_period(r);
	evo_robot_status st = {.tick = -1};
	int rc = 0, quit = 0, shot = 0, started = 0;
	double drawn = 0;
	evo_q16 qin[EVO_MAX_SENSORS], qout[EVO_MAX_ACTUATORS];
	for (long e = 1; (o->episodes == 0 || e <= o->episodes) && !quit &&
			 !shot && !evo_cmd_stop_requested && rc == 0;
	     e++) {
		evo_state_reset(m, state);
		if (evo_robot_conn_start(r, e, evo_run_grid_seed(seed, e),
					 evo_run_episode_seed(seed, e), err)) {
			rc = -1;
			break;
		}
		started = 1;
		long ticks = 0; /* the robot's tick count when it ended */
		int end = 0;
		while (!quit) {
			end = evo_robot_conn_next(r, v ? 15 : 200, err);
			evo_robot_conn_status(r, &st);
			if (end < 0 || end == 1)
				break;
			if (end == 0 && o->ticks && st.tick >= o->ticks)
				break; /* the tick after the last: its reward */
			if (end == 0) {
				evo_robot_conn_sensors(r, qin);
				for (unsigned i = 0; i < m->n_sensors; i++)
					rv.sensor[i] =
					    evo_q16_to_double(qin[i]);
				evo_mind_step(m, state, qin, qout);
				for (unsigned i = 0; i < m->n_actuators; i++)
					rv.actuator[i] =
					    evo_q16_to_double(qout[i]);
				if (evo_robot_conn_answer(r, qout, err)) {
					end = -1;
					break;
				}
				if (trace)
					evo_trace_tick(trace, (long)st.tick, m,
						       qin, qout, state);
				for (int i = 0; i < rv.p.influence.n; i++)
					rv.influence[i] = evo_q16_to_double(
					    state->influence[i]);
				rv.p.tick = (long)st.tick;
				ticks = (long)st.tick + 1;
			}
			robot_view_update(&rv, r, e);
			if (v) {
				quit = robot_keys(v, &rv, err);
				double t = evo_clock_now();
				if (t - drawn >= 1.0 / 30) {
					evo_viewer_draw_remote(v, &rv.p);
					drawn = t;
				}
			}
			if (end == 0 && o->ticks && ticks >= o->ticks) {
				/* the tick after the last one answered, for
				 * the reward it carries; not answered */
				double until =
				    evo_clock_now() + 4 * period + 0.25;
				while ((end = evo_robot_conn_next(r, 20,
								  err)) == 2 &&
				       evo_clock_now() < until)
					;
				evo_robot_conn_status(r, &st);
				break;
			}
		}
		if (end < 0 && !evo_cmd_stop_requested) {
			rc = -1;
			break;
		}
		if (end == 1 || (end == 0 && st.tick >= ticks))
			ticks = (long)st.tick;
		robot_view_update(&rv, r, e);
		printf("episode %ld: reward %.6f over %ld ticks\n", e,
		       st.reward, ticks);
		fflush(stdout);
		if (o->screenshot) {
			if (robot_screenshot(v, &rv, o->screenshot, err))
				rc = -1;
			shot = 1;
		}
		if (end < 0)
			break; /* stopped */
	}
	if (started)
		evo_robot_conn_report(r);
	evo_robot_conn_close(r);
	free(mem);
	return rc;
}
