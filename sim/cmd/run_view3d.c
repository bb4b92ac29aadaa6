/* `evo run` of a 3D task in the 3D view (cmd/run_internal.h): its panel
 * and the window's loop; --screenshot saves the frame at --ticks. */
#define _POSIX_C_SOURCE 200809L
#include "cmd/run_internal.h"

#include <stdio.h>

#include "base/number.h"

/* ---- DEMO3DSIM in the 3D view ------------------------------------------- */

static const char *const help3d[] = {
    "space pause   n step", "up/down speed r reset", "drag turn  right pan",
    "wheel/+- zoom s shot", "c follow      q quit"};

/* The panel of a 3D task: the tick, the rewards, each skill's influence,
 * and the robot's sensors and commands as its mind reads and writes them. */
evo_viewer_panel evo_run_panel3d(panel_data *pd, const evo_sim *s, long e,
				 const char *title, int follow)
{
	const evo_scene3d *sc = s->scene3d;
	const evo_bot *b = &sc->bot[0];
	const evo_mind *m = &s->mind->mind;
	int n = m->n_skills < 256 ? (int)m->n_skills : 256;
	for (int i = 0; i < n; i++) {
		pd->names[i] = evo_mind_skill_name(m, (unsigned)i);
		pd->infl[i] = evo_q16_to_double(s->state->influence[i]);
	}
	for (unsigned i = 0; i < m->n_sensors; i++) {
		pd->sensor_name[i] = evo_mind_sensor_name(m, i);
		pd->sensor[i] = b->sensor[s->sensor_map[i]].value;
	}
	for (unsigned i = 0; i < m->n_actuators; i++) {
		pd->actuator_name[i] = evo_mind_actuator_name(m, i);
		pd->actuator[i] = b->actuator[s->actuator_map[i]].command;
	}
	evo_viewer_panel p = {
	    .title = title,
	    .tick = sc->tick,
	    .episode = (int)e,
	    .step_reward = sc->step_reward,
	    .episode_reward = sc->episode_reward,
	    .influence.n = n,
	    .influence.name = pd->names,
	    .influence.value = pd->infl,
	    .bot_name = b->name,
	    .bot_reward = s->has_teams ? b->reward : sc->episode_reward,
	    .sensors.n = (int)m->n_sensors,
	    .sensors.name = pd->sensor_name,
	    .sensors.value = pd->sensor,
	    .actuators.n = (int)m->n_actuators,
	    .actuators.name = pd->actuator_name,
	    .actuators.value = pd->actuator,
	    .following = follow,
	    .n_help = 5,
	    .help = help3d,
	};
	return p;
}

/* DEMO3DSIM in a window: as run_viewer, real time (30 ticks a second)
 * times the speed; --screenshot saves the frame at --ticks and ends. */
int evo_run_viewer3d(evo_sim *s, evo_view3d *v, const run_opts *o,
		     uint64_t seed, evo_err *err)
{
	static panel_data pd;
	long e = 1, t = 0;
	int follow = 1, paused = 0;
	if (evo_sim_reset(s, 1, evo_run_grid_seed(seed, 1),
			  evo_run_episode_seed(seed, 1), err))
		return -1;
	evo_view3d_aim(v, s->scene3d);
	double speed = 1.0, next = evo_clock_now();
	for (;;) {
		if (evo_cmd_stop_requested)
			return 0;
		int steps = paused ? 0 : 1;
		evo_view_action a;
		while ((a = evo_view3d_poll(v)) != EVO_VIEW_NONE) {
			if (a == EVO_VIEW_QUIT)
				return 0;
			if (evo_run_playback(a, &paused, &steps, &speed, &t))
				continue;
			if (a == EVO_VIEW_CAMERA)
				follow = !follow;
			else if (a == EVO_VIEW_FREE)
				follow = 0;
			else if (a == EVO_VIEW_SCREENSHOT) {
				const char *path =
				    evo_run_shot_path(s->core->tick);
				evo_run_shot_said(
				    evo_view3d_screenshot(v, path, err), path,
				    err);
			}
		}
		if (t < 0) {
			t = 0;
			if (evo_sim_reset(s, (int)e, evo_run_grid_seed(seed, e),
					  evo_run_episode_seed(seed, e), err))
				return -1;
		}
		int ended = evo_run_steps(s, o, steps, e, &t, NULL, NULL, err);
		if (ended < 0)
			return -1;
		if (ended) {
			if (o->episodes && e >= o->episodes)
				return 0;
			e++;
			t = -1;
		}
		evo_viewer_panel p =
		    evo_run_panel3d(&pd, s, e, o->task, follow);
		p.speed = speed;
		p.paused = paused;
		evo_view3d_draw(v, s->scene3d, follow ? 0 : -1, &p);
		if (o->screenshot && t >= o->ticks) {
			if (evo_view3d_screenshot(v, o->screenshot, err))
				return -1;
			printf("saved %s (tick %ld)\n", o->screenshot,
			       s->core->tick);
			return 0;
		}
		evo_run_pace(&next, speed);
	}
}
