/* evo — private to sim/cmd/: what the files of `evo run` share (run.c
 * loads the task and picks the run, run_args.c reads the options,
 * run_headless.c runs without a window and drives a remote simulator,
 * run_view.c shows a 2D run in the viewer or draws its frames off
 * screen, run_view3d.c a 3D run in the 3D view, run_robot.c drives a
 * robot). No other folder may include it. */
#ifndef EVO_RUN_INTERNAL_H
#define EVO_RUN_INTERNAL_H

#include <signal.h>
#include <stdint.h>
#include <stdio.h>

#include "base/clock.h"
#include "base/err.h"
#include "cmd/stop.h"
#include "mind/task.h"
#include "remote/robot.h"
#include "tasksim/tasksim.h"
#include "viewer/view3d.h"
#include "viewer/viewer.h"

#define RUN_MAX_NETS 64

typedef struct run_opts {
	const char *task;
	int headless;
	uint64_t seed;
	int seed_set;
	long episodes; /* 0 with the viewer: until the window is closed */
	long ticks;    /* per episode; 0: until a control function ends it */
	const char *trace;
	const char *screenshot; /* viewer: save a PNG after `ticks` ticks */
	int trail;		/* viewer: draw the bot's path (--trail) */
	long env;		/* OPENENDED: show admitted environment N
				 * (--env N), 0: none */
	char env_net[1200];	/* its solver's .net (a --net SOURCE) */
	char env_task[1300];	/* its hierarchy's task when skills were added */
	const char *record;	/* frames of the run: a folder or a video */
	long record_every;	/* a frame every N ticks (0: not given) */
	int camera; /* 0 not given (the scene), 1 the scene, 2 a point, 3
		     * the bot, as the viewer follows it */
	double camera_x, camera_y;
	double zoom;	     /* 0: not given (1) */
	const char *can;     /* DEMOREMOTE: the robot's CAN URL */
	long threads;	     /* LEARNSIM: 0 for one per core */
	long generations;    /* LEARNSIM: 0 for NUMGEN */
	const char *run_dir; /* LEARNSIM */
	int resume;
	int no_save; /* LEARNSIM: the champion stays in the run folder */
	evo_net_choice net[RUN_MAX_NETS]; /* --net SKILL=SOURCE */
	unsigned n_nets;
	char net_arg[RUN_MAX_NETS][EVO_NAME_MAX]; /* each SKILL */
} run_opts;

/* Read evo run's arguments into o: 0, or -1 with the reason printed. */
int evo_run_parse_args(int argc, char **argv, run_opts *o);

/* The seeds of episode e: the grid's and the rest's, from (seed, e). */
uint64_t evo_run_grid_seed(uint64_t seed, long e);
uint64_t evo_run_episode_seed(uint64_t seed, long e);

/* A trace is written to a new file beside FILE (evo_create_beside, which
 * writes through no planted link) and renamed when the run ends well: a
 * failed run leaves nothing behind. */
typedef struct trace_file {
	FILE *f;
	char tmp[1100];
	const char *path;
} trace_file;

int evo_run_trace_open(trace_file *t, const char *path, evo_err *err);
/* keep 0: the file is dropped (a failed run); err is then left alone. */
int evo_run_trace_close(trace_file *t, int keep, evo_err *err);

/* The line of an episode that ended at tick t, with its outcome. */
int evo_run_print_episode(evo_sim *s, long e, long t, evo_err *err);

/* A window's ticks of a frame: up to `steps` ticks of episode e, at tick
 * *t, after_tick(ctx, s) after each (may be NULL); when the episode ends
 * (the environment ends it, or --ticks without --screenshot) its line
 * printed: 1 (*t then the ticks it lasted); else 0; -1 with err set. */
int evo_run_steps(evo_sim *s, const run_opts *o, int steps, long e, long *t,
		  void (*after_tick)(void *ctx, const evo_sim *s), void *ctx,
		  evo_err *err);

/* DEMOSIM without a window: o->episodes episodes. */
int evo_run_headless(evo_sim *s, const run_opts *o, uint64_t seed,
		     evo_err *err);

/* A state of mind m, laid out in memory of its own: that memory (free
 * it after the run), or NULL with err set. */
void *evo_run_mind_state(const evo_mind *m, evo_state **state, evo_err *err);

/* DEMOREMOTESIM: the mind here, the world in a remote simulator. */
int evo_run_remote_sim(const evo_task *task, const run_opts *o, uint64_t seed,
		       FILE *trace, evo_err *err);

/* A window's frame pacing: *next one frame on (30 a second times speed;
 * after a stall of half a second, from now), and a sleep until then. */
void evo_run_pace(double *next, double speed);

/* The viewer's window, and a screenshot drawn without one. */
#define VIEW_W 1024
#define VIEW_H 720

/* What the viewer's panel shows: the tick, the episode, the rewards and
 * each skill's live influence; in a team task, the teams, and the
 * selected bot's own sensors, actuators and influences. */
typedef struct panel_data {
	const char *names[256];
	double infl[256];
	const char *team_name[EVO_MAX_TEAMS];
	const char *sensor_name[EVO_MAX_SENSORS];
	double sensor[EVO_MAX_SENSORS];
	const char *actuator_name[EVO_MAX_ACTUATORS];
	double actuator[EVO_MAX_ACTUATORS];
} panel_data;

/* The playback actions both views share: pause, one step, faster,
 * slower (1/16 to 64 times real time), the episode again (*t = -1).
 * 1 when a was one of them. */
int evo_run_playback(evo_view_action a, int *paused, int *steps, double *speed,
		     long *t);

/* The s key's screenshot in both views: the file it goes to at `tick`
 * (evo-screenshot-TICK.png, in a static buffer), and saying how saving
 * it went (rc: the view's screenshot's), err cleared for the run to go
 * on. */
const char *evo_run_shot_path(long tick);
void evo_run_shot_said(int rc, const char *path, evo_err *err);

/* DEMOSIM in a window: real time (30 ticks a second) times the speed,
 * with pause, single step, speed and reset keys. */
int evo_run_viewer(evo_sim *s, evo_viewer *v, const run_opts *o, uint64_t seed,
		   evo_err *err);

/* --record: the run's frames drawn off screen, into a folder or a video
 * (a 3D task's by v3, the 3D view off screen). */
int evo_run_record_frames(evo_sim *s, const run_opts *o, uint64_t seed,
			  evo_view3d *v3, evo_err *err);

/* --screenshot without a window: the frame at --ticks, drawn off screen
 * (a 3D task's by v3). */
int evo_run_screenshot_headless(evo_sim *s, const run_opts *o, uint64_t seed,
				evo_view3d *v3, evo_err *err);

/* The panel of a 3D task, in its window and in its frames off screen. */
evo_viewer_panel evo_run_panel3d(panel_data *pd, const evo_sim *s, long e,
				 const char *title, int follow);

/* DEMO3DSIM in the 3D view. */
int evo_run_viewer3d(evo_sim *s, evo_view3d *v, const run_opts *o,
		     uint64_t seed, evo_err *err);

/* DEMOREMOTE: the mind here answers a robot's ticks, over LCM or CAN; v,
 * when not NULL, shows the robot's frame. */
int evo_run_robot(const evo_task *task, const run_opts *o, uint64_t seed,
		  FILE *trace, evo_viewer *v, evo_err *err);

#endif
