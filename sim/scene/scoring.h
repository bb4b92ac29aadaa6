/* evo — how an episode is scored, in either dimension (docs/architecture.md,
 * "Where the layout is going", step 3): the reward and control functions
 * (EvoAgents' RW_ and CF_ classes, tutorial sections 6.3 and 6.4), an
 * environment's own metrics, and the hooks Lua (or a test) hangs on a
 * scene (a Lua reward or control, post_step). Defined once here; the 2D
 * scene (world2d/scene.h) and the 3D one (world3d/scene3d.h) keep them in
 * their own arrays and hand each step to evo_score_step, with an
 * evo_score_ops saying how to read their bots.
 *
 * Which kinds exist in which dimension is said in kinds.c's rows, and
 * nowhere else: a kind whose row lacks the scene's dimension is refused
 * when it is added, with its name. A kind only one dimension has
 * (Collect and Gather: objects carried or gathered, 2D) is computed by
 * that scene's `own_reward`, which the other leaves NULL. */
#ifndef EVO_SCORING_H
#define EVO_SCORING_H

#include "base/err.h"
#include "scene/kinds.h"

#define EVO_REWARD_MAX_SENSORS 16
#define EVO_SCENE_MAX_METRICS  16 /* an environment's own metrics, at most */
#define EVO_METRIC_NAME_MAX    32 /* a metric's name, with its NUL */
#define EVO_SCENE_MAX_TEAMS    12 /* teams of bots (docs/teams.md) */

/* What a target option names besides an element (2D; a 3D target is an
 * element or none). */
#define EVO_TARGET_NONE		  (-1)
#define EVO_TARGET_NEAREST_OBJECT (-2) /* the nearest active, free object */
/* The nearest bot of another team, or of the bot's own (docs/teams.md). */
#define EVO_TARGET_NEAREST_OPPONENT (-3)
#define EVO_TARGET_NEAREST_TEAMMATE (-4)

/* ---- reward and control functions ----------------------------------- */

/* Whom a reward pays (docs/teams.md): its bot (and so the bot's team),
 * a team as a whole, or only the scene's total. Every reward counts in
 * the scene's episode_reward. */
typedef enum evo_scope {
	EVO_SCOPE_BOT = 0,
	EVO_SCOPE_TEAM,
	EVO_SCOPE_SCENE,
} evo_scope;

typedef struct evo_reward_def {
	evo_reward_kind kind;
	evo_scope scope;
	int team; /* EVO_SCOPE_TEAM: the team paid */
	int bot;
	double k, k2;
	double threshold;
	int target; /* element (zone for Collect) */
	int n_sensors;
	int sensor[EVO_REWARD_MAX_SENSORS]; /* indices into the bot's sensors */
	int lua_ref; /* EVO_RW_LUA: a registry reference */
} evo_reward_def;

/* k 1, threshold 0.5, no target, no Lua function. */
evo_reward_def evo_default_reward_def(evo_reward_kind kind);

typedef struct evo_reward {
	evo_reward_def def;
	double previous; /* ClosingOnTarget: last distance, -1 for none */
	double total;	 /* this episode */
} evo_reward;

typedef struct evo_control_def {
	evo_control_kind kind;
	int bot;
	long ticks;
	int target;
	int sensor;
	double threshold;
	int lua_ref;
} evo_control_def;

/* ticks 1000, threshold 0.5, no target, sensor or Lua function. */
evo_control_def evo_default_control_def(evo_control_kind kind);

typedef struct evo_control {
	evo_control_def def;
	long counter;
} evo_control;

/* ---- an environment's own metrics ------------------------------------ */

/* A named figure an environment reports for each episode, beside the
 * reward (time spent in a zone, objects delivered, distance travelled):
 * `evo run` prints it on the episode's line and LEARNSIM logs it
 * (docs/lua.md, "Metrics of your own"). Declared once, before the first
 * episode; its value is 0 at every reset and whatever the environment
 * makes it during the episode. */
typedef struct evo_metric {
	char name[EVO_METRIC_NAME_MAX];
	double value; /* this episode's so far; always finite */
} evo_metric;

/* Declare a metric in metric[0 .. *n): a name of letters, digits and '_'
 * that does not start with a digit, at most EVO_METRIC_NAME_MAX - 1
 * characters; at most EVO_SCENE_MAX_METRICS of them. Returns its index
 * (the one it already has when the name is declared), or -1 with err
 * set. */
int evo_metric_add(evo_metric *metric, int *n, const char *name, evo_err *err);
/* Set a metric's value: 0, or -1 with err set when the index names none
 * or the value is not finite (the metric keeps its value). */
int evo_metric_set(evo_metric *metric, int n, int k, double value,
		   evo_err *err);
/* The metric of that name, or -1. */
int evo_metric_find(const evo_metric *metric, int n, const char *name);

/* ---- hooks ------------------------------------------------------------ */

/* Lua (or a test) can hook into a scene of either dimension. Each hook
 * returns 0, or -1 with *err (the scene's) set; the step then fails. */
typedef struct evo_scene_hooks {
	void *ctx;
	int (*reward)(void *ctx, evo_err *err, const evo_reward *r,
		      double *out);
	int (*control)(void *ctx, evo_err *err, const evo_control *c,
		       int *next);
	/* After each step's rewards, before its controls (EvoAgents'
	 * postStepOps). */
	int (*post_step)(void *ctx, evo_err *err);
} evo_scene_hooks;

/* ---- what the rewards read of a scene ---------------------------------- */

/* How the functions below read the scene they score, filled by each
 * dimension (world2d/rewards.c, world3d/rewards3d.c); its bots' count,
 * their sensors' values and whom a reward is paid to are the scene's
 * core's (scene/core.h: the scene scored is a scene's core). Bot and sensor
 * indices were checked when the reward or control was added (each scene's
 * add, by kinds.c's rows for the dimension); a target may be gone. */
typedef struct evo_score_ops {
	/* contacts of bot this tick with anything but the ground */
	int (*touching)(const void *sc, int bot);
	/* bot's velocity and the unit vector it faces, in the world's
	 * frame (z 0 in 2D) */
	void (*motion)(const void *sc, int bot, double v[3], double ahead[3]);
	/* from bot's centre to target's; -1 when there is no target now */
	double (*distance)(const void *sc, int bot, int target);
	/* the sum of (2c - 1)^2 over the commands c (clamped to [0, 1], NaN
	 * 0.5) of the actuators that move bot */
	double (*effort)(const void *sc, int bot);
	/* the value of a kind of this dimension only (Collect, Gather); NULL
	 * when there is none */
	double (*own_reward)(void *sc, const evo_reward *r);
} evo_score_ops;

/* What the scoring reads of a scene's core (scene/core.h; core.c and
 * view.c define them): how many bots it has, the last value of bot's
 * sensor s (NaN for none), whether bot touched element `target` this
 * tick (NextOnCollisionWithTarget: an object that is on, or a cylinder's,
 * box's or sphere's obstacle, through the backend), and paying reward
 * r's value v to whom it is for (evo_scope: its bot and the bot's team,
 * or a team; the scene's total has it in any case). */
int evo_core_n_bots(const void *core);
double evo_core_sensor(const void *core, int bot, int s);
int evo_core_touching(const void *core, int bot, int target);
void evo_core_pay(void *core, const evo_reward *r, double v);

/* The scene being scored: how to read it, the scene itself, its hooks and
 * its error. */
typedef struct evo_scored {
	const evo_score_ops *ops;
	void *sc;
	const evo_scene_hooks *hooks;
	evo_err *err;
} evo_scored;

/* What a command c adds to Effort: (2c - 1)^2, c clamped to [0, 1] and
 * NaN read as 0.5. */
double evo_effort_term(double c);

/* One reward's value for the step just taken, added to r->total (0 on a
 * hook error, which sets *s->err and *failed). A reward whose bot index
 * names no bot gives 0; a value that is not finite gives 0. */
double evo_reward_compute_in(const evo_scored *s, evo_reward *r, int *failed);
/* 1: end the episode; 0: go on; -1: hook error. */
int evo_control_check_in(const evo_scored *s, evo_control *c);
/* Forget the previous distance and the episode's total; start counting
 * again. */
void evo_reward_reset(evo_reward *r);
void evo_control_reset(evo_control *c);

/* Steps 5 of the tick, after the physics: every reward paid (into
 * *step_reward and *episode_reward, and through ops->pay), the post-step
 * hook, then every control. 1 when a control ends the episode, 0 when it
 * goes on, -1 with *s->err set when a hook failed. */
int evo_score_step(const evo_scored *s, evo_reward *reward, int n_rewards,
		   evo_control *control, int n_controls, double *step_reward,
		   double *episode_reward);

#endif
