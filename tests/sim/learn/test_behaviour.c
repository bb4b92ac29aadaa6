/* What an episode did (evo_sim_behaviour, evo_sim_solved; docs/lua.md,
 * "What an episode did"), as the LEARNSIM evaluator reports it: without
 * env.behaviour, the bot's final position scaled into the box around the
 * environment's walls, worked out by hand for a bot that stands still;
 * env.behaviour's values averaged over the repetitions; env.solved held
 * only when every repetition solved; whatever else the environment returns
 * refused with the line of the function and what was wrong; a cluster
 * rank's result with a behaviour outside [0, 1] refused. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cluster/cluster_messages.h"
#include "harness.h"
#include "learn/evaluate.h"
#include "mind/net_build.h"
#include "support/cli.h"

static evo_netdesc *zero_net; /* both wheels neutral: the bot stays put */

/* An arena of two walls: boxes spanning x 0..100 at y -2..0 and 40..42,
 * so its bounds are x 0..100, y -2..42; the bot starts at (20, 9). */
static const char env_head[] =
    "local env = {}\n"
    "local episode = 0\n"
    "function env.init(scene, task)\n"
    "  scene:box{ x = 50, y = -1, half_width = 50, half_height = 1 }\n"
    "  scene:box{ x = 50, y = 41, half_width = 50, half_height = 1 }\n"
    "  local bot = scene:bot{ x = 20, y = 9 }\n"
    "  scene:control('NextOnTimeout', { bot = bot, ticks = 40 })\n"
    "end\n"
    "function env.reset(scene, e) episode = e end\n";

/* A copy of minds/Avoid whose LEARNSIM task runs Envs/Beh.lua, made of
 * env_head, `tail` and "return env"; its task's path in task. */
static int make_env(const char *name, const char *tail, char *task,
		    size_t cap)
{
	if (cli_sh("rm -rf %s/%s && mkdir -p %s/%s && cp -r minds/Avoid "
		   "%s/%s/ && printf 'TYPE:LEARNSIM\\nBOTMODEL:BotType8\\n"
		   "MASTERSKILL:Avoid\\nLEARNINGSKILL:Avoid\\nENV:Beh\\n"
		   "LEARNINGMETHOD:NEAT\\nNUMGEN:1\\nEVALREP:2\\n"
		   "TICKLIM:40\\n' > %s/%s/Avoid/Tasks/Beh.simbatch",
		   cli_tmp, name, cli_tmp, name, cli_tmp, name, cli_tmp,
		   name))
		return -1;
	size_t n = strlen(env_head) + strlen(tail) + 32;
	char *text = malloc(n);
	snprintf(text, n, "%s%sreturn env\n", env_head, tail);
	int rc = cli_write(text, "%s/%s/Avoid/Envs/Beh.lua", cli_tmp, name);
	free(text);
	snprintf(task, cap, "%s/%s/Avoid/Tasks/Beh.simbatch", cli_tmp, name);
	return rc;
}

/* Evaluate the zero network twice (two candidates) in the environment
 * of `tail`; 0 with res filled, or -1 with err. */
static int evaluate_in(const char *name, const char *tail,
		       evo_eval_result *res, evo_err *err)
{
	char task[512];
	if (make_env(name, tail, task, sizeof task))
		return evo_fail(err, "could not make %s", name);
	evo_eval_def def = {.task_path = task, .threads = 2, .seed = 3};
	evo_evaluator *ev = evo_evaluator_create(&def, err);
	if (!ev)
		return -1;
	const evo_netdesc *c[2] = {zero_net, zero_net};
	int rc = evo_evaluate(ev, c, 2, 0, res, err);
	evo_evaluator_destroy(ev);
	return rc;
}

TEST(without_env_behaviour_it_is_the_final_position_in_the_walls_bounds)
{
	evo_eval_result res[2];
	evo_err err = {{0}};
	CHECK_EQ_INT(evaluate_in("plain", "", res, &err), 0);
	if (err.msg[0])
		printf("  %s\n", err.msg);
	for (int i = 0; i < 2; i++) {
		CHECK_EQ_INT(res[i].n_behaviour, 2);
		/* (20 - 0) / 100 and (9 + 2) / 44 */
		CHECK(fabs(res[i].behaviour[0] - 0.2) < 1e-9);
		CHECK(fabs(res[i].behaviour[1] - 0.25) < 1e-9);
		CHECK_EQ_INT(res[i].solved, 0); /* no env.solved */
	}
	printf("  behaviour (%.12f, %.12f)\n", res[0].behaviour[0],
	       res[0].behaviour[1]);
}

TEST(env_behaviour_is_averaged_over_the_repetitions)
{
	evo_eval_result res[2];
	evo_err err = {{0}};
	CHECK_EQ_INT(evaluate_in("own",
				 "function env.behaviour(scene, bot)\n"
				 "  local x = bot:pose()\n"
				 "  return { episode / 4, x / 100, 1 }\n"
				 "end\n"
				 "function env.solved(scene, bot)\n"
				 "  return true\n"
				 "end\n",
				 res, &err),
		     0);
	if (err.msg[0])
		printf("  %s\n", err.msg);
	CHECK_EQ_INT(res[0].n_behaviour, 3);
	/* episodes 1 and 2: (0.25 + 0.5) / 2 */
	CHECK(fabs(res[0].behaviour[0] - 0.375) < 1e-12);
	CHECK(fabs(res[0].behaviour[1] - 0.2) < 1e-9);
	CHECK(res[0].behaviour[2] == 1);
	CHECK_EQ_INT(res[0].solved, 1);
	CHECK_EQ_INT(res[1].solved, 1);
}

TEST(solved_needs_every_repetition)
{
	evo_eval_result res[2];
	evo_err err = {{0}};
	CHECK_EQ_INT(evaluate_in("once",
				 "function env.solved(scene, bot)\n"
				 "  return episode == 1\n"
				 "end\n",
				 res, &err),
		     0);
	CHECK_EQ_INT(res[0].solved, 0);
	CHECK_EQ_INT(res[0].n_behaviour, 2);
}

/* In 3D, EXP3D_Avoid's walls are boxes 0.1 m thick around a 10 m square
 * (their outer faces at +-5.1 m), and the bot starts at its centre: a bot
 * that stands still is at (0.5, 0.5), give or take the millimetres its
 * wheels settle. */
TEST(in_3d_too)
{
	evo_err err = {{0}};
	evo_eval_def def = {.task_path =
				"minds/Wheeled3D/Tasks/Avoid3D-NEAT.simbatch",
			    .threads = 1,
			    .seed = 3,
			    .reps = 1,
			    .ticks = 30};
	evo_evaluator *ev = evo_evaluator_create(&def, &err);
	CHECK(ev != NULL);
	if (!ev) {
		printf("  %s\n", err.msg);
		return;
	}
	evo_netdesc net;
	double w[18] = {0};
	CHECK(evo_net_build_layered(8, 2, 0, 1, EVO_ACT_SIGMOID,
				    EVO_ACT_SIGMOID, w, &net) == EVO_OK);
	const evo_netdesc *c[1] = {&net};
	evo_eval_result res[1];
	CHECK_EQ_INT(evo_evaluate(ev, c, 1, 0, res, &err), 0);
	CHECK_EQ_INT(res[0].n_behaviour, 2);
	CHECK(fabs(res[0].behaviour[0] - 0.5) < 1e-3);
	CHECK(fabs(res[0].behaviour[1] - 0.5) < 1e-3);
	printf("  3D behaviour (%.6f, %.6f)\n", res[0].behaviour[0],
	       res[0].behaviour[1]);
	evo_evaluator_destroy(ev);
}

/* env.behaviour or env.solved written at line 10 of Beh.lua (the line
 * after env_head) returning `what`: the batch fails with that line and
 * `says`. */
static void refused(const char *name, const char *fn, const char *what,
		    const char *says)
{
	char tail[256];
	snprintf(tail, sizeof tail,
		 "function env.%s(scene, bot)\n  return %s\nend\n", fn, what);
	evo_eval_result res[2];
	evo_err err = {{0}};
	CHECK_EQ_INT(evaluate_in(name, tail, res, &err), -1);
	CHECK_CONTAINS(err.msg, strcmp(name, "grows") ? "Beh.lua:10: "
						       : "Beh.lua: ");
	CHECK_CONTAINS(err.msg, says);
	CHECK_CONTAINS(err.msg, "at its end");
	printf("  %s\n", err.msg);
}

TEST(what_is_not_a_behaviour_is_refused_at_its_line)
{
	refused("big", "behaviour", "{ 0.5, 1.5 }",
		"env.behaviour's value 2 is 1.5, not in [0, 1]");
	refused("nan", "behaviour", "{ 0/0 }", "value 1 is");
	refused("str", "behaviour", "{ '0.5' }",
		"value 1 is a string, not a number");
	refused("none", "behaviour", "{}", "returned 0 values");
	refused("many", "behaviour", "{ 0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0 }",
		"returned 17 values; a behaviour is 1 to 16 numbers");
	refused("num", "behaviour", "0.5", "returned a number, not a list");
	refused("grows", "behaviour",
		"episode == 1 and { 0.5 } or { 0.5, 0.5 }",
		"returned 2 values, where repetition 1's returned 1");
	refused("yes", "solved", "1", "env.solved returned a number, not a "
				      "boolean");
}

/* A rank's result travels as evo_eval_result: a behaviour no evaluation
 * gives is refused before the learning loop sees it. */
TEST(a_ranks_behaviour_outside_0_1_is_refused)
{
	int32_t head[3] = {4, 1, 0};
	unsigned char msg[sizeof head + sizeof(evo_eval_result)];
	evo_eval_result r;
	memset(&r, 0, sizeof r);
	r.n_behaviour = 2;
	r.behaviour[0] = 0.5;
	r.behaviour[1] = NAN;
	memcpy(msg, head, sizeof head);
	memcpy(msg + sizeof head, &r, sizeof r);
	evo_eval_result out;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_cluster_check_result(msg, sizeof msg, 1, "node7", 4,
					      1, &out, &err),
		     -1);
	CHECK_CONTAINS(err.msg, "candidate 4: a behaviour");
	r.behaviour[1] = 1;
	memcpy(msg + sizeof head, &r, sizeof r);
	CHECK_EQ_INT(evo_cluster_check_result(msg, sizeof msg, 1, "node7", 4,
					      1, &out, &err),
		     0);
	CHECK(out.behaviour[1] == 1);
	r.n_behaviour = EVO_SIM_MAX_BEHAVIOUR + 1;
	memcpy(msg + sizeof head, &r, sizeof r);
	CHECK_EQ_INT(evo_cluster_check_result(msg, sizeof msg, 1, "node7", 4,
					      1, &out, &err),
		     -1);
}

int main(void)
{
	if (cli_setup("behaviour"))
		return 1;
	zero_net = calloc(1, sizeof *zero_net);
	double w[24] = {0};
	if (evo_net_build_layered(11, 2, 0, 1, EVO_ACT_SIGMOID,
				  EVO_ACT_SIGMOID, w, zero_net) != EVO_OK)
		return 1;
	RUN(without_env_behaviour_it_is_the_final_position_in_the_walls_bounds);
	RUN(env_behaviour_is_averaged_over_the_repetitions);
	RUN(solved_needs_every_repetition);
	RUN(in_3d_too);
	RUN(what_is_not_a_behaviour_is_refused_at_its_line);
	RUN(a_ranks_behaviour_outside_0_1_is_refused);
	free(zero_net);
	cli_cleanup();
	return test_summary();
}
