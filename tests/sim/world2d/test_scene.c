/* A scene's storage (sim/world2d/scene.c) and its episode (step.c): an
 * environment's own metrics are declared once, under names a log.csv
 * header and an episode line can carry, at most EVO_SCENE_MAX_METRICS;
 * they keep only finite values and are 0 again at every reset. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "support/scenes.h"
#include "world2d/scene.h"

TEST(metrics_are_declared_once_in_order)
{
	evo_scene *sc = scene_with_bot(0, 0, 0);
	CHECK_EQ_INT(sc->n_metrics, 0);
	CHECK_EQ_INT(evo_scene_add_metric(sc, "in_zone"), 0);
	CHECK_EQ_INT(evo_scene_add_metric(sc, "Delivered2"), 1);
	CHECK_EQ_INT(evo_scene_add_metric(sc, "_x"), 2);
	/* a name declared again is the same metric */
	CHECK_EQ_INT(evo_scene_add_metric(sc, "in_zone"), 0);
	CHECK_EQ_INT(sc->n_metrics, 3);
	CHECK_EQ_STR(sc->metric[1].name, "Delivered2");
	CHECK_EQ_INT(evo_scene_find_metric(sc, "_x"), 2);
	CHECK_EQ_INT(evo_scene_find_metric(sc, "in"), -1);
	evo_scene_destroy(sc);
}

TEST(a_metric_name_is_an_identifier_of_at_most_31_characters)
{
	evo_scene *sc = scene_with_bot(0, 0, 0);
	const char *bad[] = {"",      "9lives", "in zone", "in,zone",
			     "x-y",   "élan",   "a:b",     "a\"b"};
	for (unsigned i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		sc->err.msg[0] = 0;
		CHECK_EQ_INT(evo_scene_add_metric(sc, bad[i]), -1);
		CHECK_CONTAINS(sc->err.msg, "is not a metric name: use letters, "
					    "digits and '_'");
	}
	char name[40];
	memset(name, 'a', 31);
	name[31] = 0;
	CHECK_EQ_INT(evo_scene_add_metric(sc, name), 0);
	name[31] = 'a';
	name[32] = 0;
	CHECK_EQ_INT(evo_scene_add_metric(sc, name), -1);
	CHECK_CONTAINS(sc->err.msg, "is longer than 31 characters");
	CHECK_EQ_INT(sc->n_metrics, 1);
	evo_scene_destroy(sc);
}

TEST(an_environment_has_at_most_16_metrics)
{
	evo_scene *sc = scene_with_bot(0, 0, 0);
	char name[16];
	for (int i = 0; i < EVO_SCENE_MAX_METRICS; i++) {
		snprintf(name, sizeof name, "m%d", i);
		CHECK_EQ_INT(evo_scene_add_metric(sc, name), i);
	}
	CHECK_EQ_INT(EVO_SCENE_MAX_METRICS, 16);
	CHECK_EQ_INT(evo_scene_add_metric(sc, "one_more"), -1);
	CHECK_CONTAINS(sc->err.msg, "metric 'one_more' is one too many: an "
				    "environment has at most 16");
	/* one already declared is no new one */
	CHECK_EQ_INT(evo_scene_add_metric(sc, "m3"), 3);
	evo_scene_destroy(sc);
}

TEST(a_metric_keeps_finite_values_and_starts_each_episode_at_0)
{
	evo_scene *sc = scene_with_bot(0, 0, 0);
	int m = evo_scene_add_metric(sc, "in_zone");
	evo_scene_reset(sc, 1, 1);
	CHECK(sc->metric[m].value == 0);
	CHECK_EQ_INT(evo_scene_set_metric(sc, m, 12.5), 0);
	CHECK(sc->metric[m].value == 12.5);
	CHECK_EQ_INT(evo_scene_set_metric(sc, m, NAN), -1);
	CHECK_CONTAINS(sc->err.msg, "metric 'in_zone': ");
	CHECK_CONTAINS(sc->err.msg, "is not a finite number");
	CHECK_EQ_INT(evo_scene_set_metric(sc, m, -INFINITY), -1);
	CHECK(sc->metric[m].value == 12.5);
	CHECK_EQ_INT(evo_scene_set_metric(sc, 1, 1), -1);
	/* the steps leave it alone; the next reset sets it to 0 */
	for (int t = 0; t < 5; t++)
		CHECK_EQ_INT(evo_scene_step(sc), 0);
	CHECK(sc->metric[m].value == 12.5);
	evo_scene_reset(sc, 2, 2);
	CHECK(sc->metric[m].value == 0);
	CHECK_EQ_INT(sc->n_metrics, 1);
	evo_scene_destroy(sc);
}

int main(void)
{
	RUN(metrics_are_declared_once_in_order);
	RUN(a_metric_name_is_an_identifier_of_at_most_31_characters);
	RUN(an_environment_has_at_most_16_metrics);
	RUN(a_metric_keeps_finite_values_and_starts_each_episode_at_0);
	return test_summary();
}
