/* evo — a task's simulation: one scene built by the task's Lua
 * environment, with the task's mind driving its first bot.
 *
 * This is what DEMOSIM runs and what each learning worker holds (its own
 * world, its own Lua state). The tick is DESIGN.md's: sensors sample, the
 * mind steps, actuators act, the physics steps, rewards add up, control
 * functions may end the episode. */
#ifndef EVO_SIM_H
#define EVO_SIM_H

#include <stdio.h>

#include "evo/evo.h"
#include "lua/lua_evo.h"
#include "mind/mindfolder.h"
#include "world2d/scene.h"

typedef struct evo_sim {
	evo_scene *scene;
	evo_lua *lua;
	const evo_mindfolder *mind; /* not owned */
	const evo_simbatch *task; /* not owned */
	int bot;		/* the bot the mind drives */
	/* botdesc order -> the bot's sensor / actuator index */
	int sensor_map[EVO_MAX_SENSORS];
	int actuator_map[EVO_MAX_ACTUATORS];
	void *state_mem;
	evo_state *state;
	evo_q16 sensors[EVO_MAX_SENSORS];     /* what the mind read this tick */
	evo_q16 actuators[EVO_MAX_ACTUATORS]; /* what it wrote */
	int episode;
	FILE *trace; /* when set, every tick is recorded (evo_sim_trace_*) */
} evo_sim;

/* Build the scene of a task: the environment ENV (from the mind folder's
 * Envs/ or lua/envs/) with bots of BOTMODEL, and bind the mind to the
 * first bot by the botdesc's names. Returns NULL with err set
 * ("file:line: ...") on a script error or a botdesc name the bot model
 * lacks. */
evo_sim *evo_sim_create(const evo_mindfolder *mind, const evo_simbatch *task,
			const char *task_path, evo_err *err);
void evo_sim_destroy(evo_sim *s);

/* Start episode `episode`: the scene's reset (grid from grid_seed, the
 * rng from episode_seed), the environment's reset hook, the mind's state
 * back to tick 0. */
int evo_sim_reset(evo_sim *s, int episode, uint64_t grid_seed,
		  uint64_t episode_seed, evo_err *err);

/* Rebind the mind after its image was rebuilt (a new candidate). */
int evo_sim_set_mind(evo_sim *s, const evo_mindfolder *mind, evo_err *err);

/* One tick. Returns 0 to go on, 1 when a control function ended the
 * episode, -1 with err set (a script error). */
int evo_sim_tick(evo_sim *s, evo_err *err);

/* The two halves of a tick without the mind, for a world served to a
 * remote mind (`evo serve`, docs/remote.md). evo_sim_sense: the sensors
 * sample, and values[i] is botdesc sensor i's reading. evo_sim_act:
 * botdesc actuator i gets commands[i], then the physics steps, rewards add
 * up and the controls may end the episode; returns as evo_sim_tick does.
 * Sensing then acting with the values evo_sim_tick's mind would read and
 * write is evo_sim_tick, to the bit. */
void evo_sim_sense(evo_sim *s, double *values);
int evo_sim_act(evo_sim *s, const double *commands, evo_err *err);

/* Traces (docs/running.md, Traces): a header naming the sensors, actuators
 * and skills, then one line per tick with the Q15.16 values the mind read
 * and wrote and each skill's influence. */
void evo_sim_trace_header(evo_sim *s);

#endif
