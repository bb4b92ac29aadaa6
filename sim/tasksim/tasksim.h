/* evo — a task's simulation: one scene built by the task's Lua
 * environment, with the task's mind driving its first bot, or, in a team
 * task (docs/teams.md), every team's mind driving each of its bots.
 *
 * This is what DEMOSIM and DEMO2DSIMMULTI run and what each learning
 * worker holds (its own world, its own Lua state). The tick is DESIGN.md's:
 * sensors sample, each bot's mind steps, actuators act, the physics steps,
 * rewards add up, control functions may end the episode.
 *
 * Agents. Every bot a mind drives is an agent, with a mind state of its
 * own; the agents of a team run their team's mind image (read-only,
 * shared), unless one is given an image of its own (a heterogeneous team
 * in learning). A one-agent task is one team of one agent, bot 0. */
#ifndef EVO_SIM_H
#define EVO_SIM_H

#include <stdio.h>

#include "evo/evo.h"
#include "lua/lua_evo.h"
#include "mind/mindfolder.h"
#include "mind/task.h"
#include "scene/core.h"
#include "world2d/scene.h"
#include "world3d/scene3d.h"

typedef struct evo_sim_team {
	char name[EVO_TEAM_NAME_MAX]; /* "" in a one-agent task */
	const evo_mindfolder *mind;   /* its image (not owned) */
	int size;		      /* its agents */
	int first;		      /* the first of them in agent[] */
	uint32_t line;		      /* its TEAM line, for messages */
	/* botdesc order -> its bots' sensor / actuator index (the bots of
	 * a team are built by one bot model, so they share these) */
	int sensor_map[EVO_MAX_SENSORS];
	int actuator_map[EVO_MAX_ACTUATORS];
} evo_sim_team;

typedef struct evo_sim_agent {
	int bot;		    /* its bot in the scene */
	int team;		    /* its team in evo_sim's team[] */
	const evo_mindfolder *mind; /* the image it runs (not owned) */
	void *state_mem;
	size_t state_cap;
	evo_state *state; /* its own */
} evo_sim_agent;

typedef struct evo_sim {
	/* The task's world: a 2D scene, or for DEMO3DSIM and LEARN3DSIM a
	 * 3D one (docs/world3d.md), the other NULL. Everything here reaches
	 * it through its core (scene/core.h: the figures, and its
	 * dimension's table for the rest), whichever it is; only the viewer
	 * and the Lua state, made for one world, read the two. */
	evo_scene *scene;
	evo_scene3d *scene3d;
	evo_scene_core *core; /* &scene->core or &scene3d->core */
	evo_lua *lua;
	const evo_mindfolder *mind; /* the first team's (not owned) */
	const evo_simbatch *task; /* not owned */
	/* The first agent, as a one-agent task has it: its bot, its team's
	 * maps, its state, and what its mind read and wrote this tick. */
	int bot;
	int sensor_map[EVO_MAX_SENSORS];
	int actuator_map[EVO_MAX_ACTUATORS];
	evo_state *state;
	evo_q16 sensors[EVO_MAX_SENSORS];
	evo_q16 actuators[EVO_MAX_ACTUATORS];
	int episode;
	FILE *trace; /* when set, every tick is recorded (evo_sim_trace_*) */
	/* Teams and agents; has_teams is 0 in a one-agent task. */
	int has_teams;
	int n_teams;
	evo_sim_team *team;
	int n_agents;
	evo_sim_agent *agent;
	char task_path[1024];
} evo_sim;

/* Build the scene of a one-agent task: the environment ENV (from the mind
 * folder's Envs/ or lua/envs/) with bots of BOTMODEL, and bind the mind
 * to the first bot by the botdesc's names. Returns NULL with err set
 * ("file:line: ...") on a script error or a botdesc name the bot model
 * lacks. */
evo_sim *evo_sim_create(const evo_mindfolder *mind, const evo_simbatch *task,
			const char *task_path, evo_err *err);

/* Build the scene of any task: a one-agent task as evo_sim_create; a team
 * task with every team's bots, each team's mind bound to each of its
 * bots. A team whose bots the environment did not make, all and only
 * SIZE of them, or whose botdesc names what its bot model lacks, is an
 * error at its TEAM line. */
evo_sim *evo_sim_create_task(const evo_task *t, const char *task_path,
			     evo_err *err);
void evo_sim_destroy(evo_sim *s);

/* Start episode `episode`: the scene's reset (grid from grid_seed, the
 * rng from episode_seed), the environment's reset hook, every agent's
 * state back to tick 0. */
int evo_sim_reset(evo_sim *s, int episode, uint64_t grid_seed,
		  uint64_t episode_seed, evo_err *err);

/* Rebind the first team's mind after its image was rebuilt (a new
 * candidate); every agent of the team then runs it. */
int evo_sim_set_mind(evo_sim *s, const evo_mindfolder *mind, evo_err *err);

/* The same for team `team`, and for one agent alone (its team's mind
 * folder with another network: a heterogeneous team). */
int evo_sim_set_team_mind(evo_sim *s, int team, const evo_mindfolder *mind,
			  evo_err *err);
int evo_sim_set_agent_mind(evo_sim *s, int agent, const evo_mindfolder *mind,
			   evo_err *err);

/* One tick. Returns 0 to go on, 1 when a control function ended the
 * episode, -1 with err set (a script error). */
int evo_sim_tick(evo_sim *s, evo_err *err);

/* The two halves of a tick without the mind, for a world served to a
 * remote mind (`evo serve`, docs/remote.md), for the first agent.
 * evo_sim_sense: the sensors sample, and values[i] is botdesc sensor i's
 * reading. evo_sim_act: botdesc actuator i gets commands[i], then the
 * physics steps, rewards add up and the controls may end the episode;
 * returns as evo_sim_tick does. Sensing then acting with the values
 * evo_sim_tick's mind would read and write is evo_sim_tick, to the bit. */
void evo_sim_sense(evo_sim *s, double *values);
int evo_sim_act(evo_sim *s, const double *commands, evo_err *err);

/* 1 for the task types that run in the 3D world: DEMO3DSIM, LEARN3DSIM,
 * DEMO3DSIMMULTI, LEARN3DSIMMULTI. */
int evo_sim_type_is_3d(const char *type);

/* The episode's figures, of either world: its reward so far, its ticks,
 * the ticks agent a's bot spent touching something, the environment's
 * metrics, and what broke the episode ("" when nothing did:
 * a 3D body that exploded). */
double evo_sim_episode_reward(const evo_sim *s);
long evo_sim_ticks(const evo_sim *s);
int evo_sim_collisions(const evo_sim *s, int agent);
int evo_sim_n_metrics(const evo_sim *s);
const char *evo_sim_metric_name(const evo_sim *s, int k);
double evo_sim_metric(const evo_sim *s, int k);
const char *evo_sim_fault(const evo_sim *s);

/* A team task's figures (docs/teams.md): what team k was paid (its bots'
 * own and its team rewards), the episode's winner (-1: none), and a bot's
 * name and what it was paid. */
double evo_sim_team_reward(const evo_sim *s, int team);
int evo_sim_winner(const evo_sim *s);
const char *evo_sim_bot_name(const evo_sim *s, int bot);
double evo_sim_bot_reward(const evo_sim *s, int bot);

/* The most numbers a behaviour descriptor has. */
#define EVO_SIM_MAX_BEHAVIOUR 16

/* At an episode's end, what it did, for novelty search and MAP-Elites
 * (docs/lua.md, "What an episode did"): the environment's
 * behaviour(scene, bot) for the first agent's bot, or when it has none,
 * the bot's position on the ground plane scaled into the arena's bounds:
 * the box around the static obstacles the environment built (2D: walls,
 * boxes, cylinders and the obstacle grid's area; 3D: boxes, cylinders and
 * spheres that are not ground), or without any, a 10 m square centred on
 * where the bot started; each value clamped to [0, 1]. Writes
 * out[0 .. EVO_SIM_MAX_BEHAVIOUR-1] and returns how many values, or -1
 * with err set (a script error, a value outside [0, 1]). */
int evo_sim_behaviour(evo_sim *s, double *out, evo_err *err);

/* At an episode's end: the environment's solved(scene, bot) for the first
 * agent's bot. Returns 0 and sets *solved to 1 or 0, or to -1 when the
 * environment has no solved function; -1 with err set on a script error
 * or a value that is not a boolean. */
int evo_sim_solved(evo_sim *s, int *solved, evo_err *err);

/* The agent that drives bot `bot`, or -1. */
int evo_sim_agent_of_bot(const evo_sim *s, int bot);

/* Traces (docs/running.md, Traces; docs/teams.md for teams): a header
 * naming the sensors, actuators and skills, then one line per tick (per
 * agent and tick in a team task) with the Q15.16 values the mind read and
 * wrote and each skill's influence. */
void evo_sim_trace_header(evo_sim *s);

#endif
