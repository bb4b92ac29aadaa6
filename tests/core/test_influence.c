/* Influence, worked by hand (docs/mind.md, "Influence"). Every expected
 * value below is computed on paper from the rules:
 *   master influence 1; child influence = sum over parents of I * o,
 *   clamped to 1; actuator = sum I*m / sum I over its writers, 0.5 with
 *   none; a skill under 0.01 is not computed. */
#include "harness.h"
#include "support/minibuild.h"

static minibuild b;

/* Q16 values are exact to about 1.5e-5; allow 2 ulp for rounding. */
#define CHECK_Q(q, want) CHECK_EQ_INT(near((q), (want)), 1)

static int near(evo_q16 q, double want)
{
	double got = evo_q16_to_double(q);
	double d = got > want ? got - want : want - got;
	if (d > 2.0 / 65536) {
		printf("    %.6f != %.6f\n", got, want);
		return 0;
	}
	return 1;
}

static const uint8_t SK = EVO_OUT_SK, MO = EVO_OUT_MO, VA = EVO_OUT_VA;

/* Master -> A (0.5) -> B (0.6): B has 0.5 * 0.6 = 0.3. B alone writes
 * M0 = 0.9, so M0 = 0.9 whatever B's influence. Master writes M1 = 0.2
 * with influence 1 and A writes M1 = 0.8 with 0.5:
 * M1 = (1 * 0.2 + 0.5 * 0.8) / 1.5 = 0.6 / 1.5 = 0.4. */
TEST(chain)
{
	mb_init(&b, 0, 2, 0);
	mb_const(&b, "Master", 2, (uint8_t[]){SK, MO}, (uint16_t[]){1, 1},
		 (double[]){0.5, 0.2});
	mb_const(&b, "A", 2, (uint8_t[]){SK, MO}, (uint16_t[]){2, 1},
		 (double[]){0.6, 0.8});
	mb_const(&b, "B", 1, (uint8_t[]){MO}, (uint16_t[]){0},
		 (double[]){0.9});
	CHECK_EQ_INT(mb_finish(&b), EVO_OK);
	evo_q16 act[2];
	mb_step(&b, NULL, act);
	CHECK_Q(b.state->influence[0], 1.0);
	CHECK_Q(b.state->influence[1], 0.5);
	CHECK_Q(b.state->influence[2], 0.3);
	CHECK_Q(act[0], 0.9);
	CHECK_Q(act[1], 0.4);
}

/* Master -> P1 (0.5), P2 (0.25); P1 -> C (0.8), P2 -> C (1.0):
 * C = 0.5 * 0.8 + 0.25 * 1.0 = 0.65. C writes M0 = 0.3 alone: 0.3. */
TEST(two_parents_share_a_child)
{
	mb_init(&b, 0, 1, 0);
	mb_const(&b, "Master", 2, (uint8_t[]){SK, SK}, (uint16_t[]){1, 2},
		 (double[]){0.5, 0.25});
	mb_const(&b, "P1", 1, (uint8_t[]){SK}, (uint16_t[]){3},
		 (double[]){0.8});
	mb_const(&b, "P2", 1, (uint8_t[]){SK}, (uint16_t[]){3},
		 (double[]){1.0});
	mb_const(&b, "C", 1, (uint8_t[]){MO}, (uint16_t[]){0},
		 (double[]){0.3});
	CHECK_EQ_INT(mb_finish(&b), EVO_OK);
	evo_q16 act[1];
	mb_step(&b, NULL, act);
	CHECK_Q(b.state->influence[3], 0.65);
	CHECK_Q(act[0], 0.3);
}

/* Master -> P1 (1.0), P2 (1.0); P1 -> C (0.7), P2 -> C (0.6):
 * 0.7 + 0.6 = 1.3, clamped to 1.0. */
TEST(shared_child_influence_clamps_to_one)
{
	mb_init(&b, 0, 1, 0);
	mb_const(&b, "Master", 2, (uint8_t[]){SK, SK}, (uint16_t[]){1, 2},
		 (double[]){1.0, 1.0});
	mb_const(&b, "P1", 1, (uint8_t[]){SK}, (uint16_t[]){3},
		 (double[]){0.7});
	mb_const(&b, "P2", 1, (uint8_t[]){SK}, (uint16_t[]){3},
		 (double[]){0.6});
	mb_const(&b, "C", 1, (uint8_t[]){MO}, (uint16_t[]){0},
		 (double[]){0.3});
	CHECK_EQ_INT(mb_finish(&b), EVO_OK);
	evo_q16 act[1];
	mb_step(&b, NULL, act);
	CHECK_Q(b.state->influence[3], 1.0);
}

/* Master copies sensor S0 to SK:A. A is a counter: +0.1 each time it is
 * computed, written to M0, and it influences B with 1.0; B writes M1 = 0.9.
 *   tick 1: S0 = 1     A = 1: computed, counter 0.1; M0 = 0.1; B = 1, M1 = 0.9
 *   tick 2: S0 = 0.005 A = 0.005 < 0.01: skipped. Nobody writes M0 or M1:
 *           both 0.5; B gets nothing from A: B = 0, also skipped
 *   tick 3: S0 = 1     A computed again: its memory held, counter 0.2 */
TEST(skill_under_threshold_is_skipped_and_keeps_its_memory)
{
	mb_init(&b, 1, 2, 0);
	mb_copy(&b, "Master", 1, (uint8_t[]){EVO_IN_SE}, (uint16_t[]){0},
		(uint8_t[]){SK}, (uint16_t[]){1});
	unsigned a = mb_counter(&b, "A", 0.1, MO, 0);
	/* A also needs the SK output to B: rebuild its outputs. */
	b.skill[a].n_out = 2;
	b.out[a][1] = (evo_image_io){.type = EVO_OUT_SK, .index = 2};
	b.net[a].n_out = 2;
	b.net[a].node[b.net[a].n_nodes++] = (evo_netdesc_node){
		.id = 101, .act = EVO_ACT_IDENTITY, .bias = EVO_Q16_ONE};
	b.net[a].out_id[1] = 101;
	mb_const(&b, "B", 1, (uint8_t[]){MO}, (uint16_t[]){1},
		 (double[]){0.9});
	CHECK_EQ_INT(mb_finish(&b), EVO_OK);
	evo_q16 act[2];
	mb_step(&b, (double[]){1.0}, act);
	CHECK_Q(act[0], 0.1);
	CHECK_Q(act[1], 0.9);
	CHECK_Q(b.state->influence[2], 1.0);
	mb_step(&b, (double[]){0.005}, act);
	CHECK(b.state->influence[1] < EVO_INFLUENCE_MIN);
	CHECK_Q(act[0], 0.5);
	CHECK_Q(act[1], 0.5);
	CHECK_Q(b.state->influence[2], 0.0);
	mb_step(&b, (double[]){1.0}, act);
	CHECK_Q(act[0], 0.2);
}

/* Just at the threshold (0.01 = 655/65536) a skill runs; one ulp below
 * it does not. */
TEST(threshold_edge)
{
	for (int below = 0; below <= 1; below++) {
		mb_init(&b, 0, 1, 0);
		double o = (EVO_INFLUENCE_MIN - below) / 65536.0;
		mb_const(&b, "Master", 1, (uint8_t[]){SK}, (uint16_t[]){1},
			 (double[]){o});
		mb_const(&b, "A", 1, (uint8_t[]){MO}, (uint16_t[]){0},
			 (double[]){0.9});
		CHECK_EQ_INT(mb_finish(&b), EVO_OK);
		evo_q16 act[1];
		mb_step(&b, NULL, act);
		CHECK_Q(act[0], below ? 0.5 : 0.9);
	}
}

/* M1 has no writer: it holds the neutral 0.5 every tick. */
TEST(actuator_written_by_nobody_is_neutral)
{
	mb_init(&b, 0, 2, 0);
	mb_const(&b, "Master", 1, (uint8_t[]){MO}, (uint16_t[]){0},
		 (double[]){0.0});
	CHECK_EQ_INT(mb_finish(&b), EVO_OK);
	evo_q16 act[2];
	for (int t = 0; t < 3; t++) {
		mb_step(&b, NULL, act);
		CHECK_Q(act[0], 0.0);
		CHECK_Q(act[1], 0.5);
	}
}

/* Master -> A (1.0), B (0.5); A writes V0 = 0.9, B writes V0 = 0.3:
 * V0 = (1 * 0.9 + 0.5 * 0.3) / 1.5 = 1.05 / 1.5 = 0.7, visible from the
 * next tick on (all readers of a tick see the same value). Master copies
 * V0 to M0, so M0 reads 0 on tick 1 and 0.7 on tick 2. */
TEST(variable_written_by_two_skills)
{
	mb_init(&b, 0, 1, 1);
	unsigned m = mb_copy(&b, "Master", 1, (uint8_t[]){EVO_IN_VA},
			     (uint16_t[]){0}, (uint8_t[]){MO},
			     (uint16_t[]){0});
	b.skill[m].n_out = 3;
	b.out[m][1] = (evo_image_io){.type = EVO_OUT_SK, .index = 1};
	b.out[m][2] = (evo_image_io){.type = EVO_OUT_SK, .index = 2};
	evo_netdesc *d = &b.net[m];
	d->n_out = 3;
	d->node[d->n_nodes++] = (evo_netdesc_node){
		.id = 101, .act = EVO_ACT_IDENTITY, .bias = EVO_Q16_ONE};
	d->node[d->n_nodes++] = (evo_netdesc_node){
		.id = 102, .act = EVO_ACT_IDENTITY, .bias = EVO_Q16_HALF};
	d->out_id[1] = 101;
	d->out_id[2] = 102;
	mb_const(&b, "A", 1, (uint8_t[]){VA}, (uint16_t[]){0},
		 (double[]){0.9});
	mb_const(&b, "B", 1, (uint8_t[]){VA}, (uint16_t[]){0},
		 (double[]){0.3});
	CHECK_EQ_INT(mb_finish(&b), EVO_OK);
	evo_q16 act[1];
	mb_step(&b, NULL, act);
	CHECK_Q(act[0], 0.0);
	CHECK_Q(b.state->var[0].value, 0.7);
	mb_step(&b, NULL, act);
	CHECK_Q(act[0], 0.7);
}

/* SD reads 0.5 + (now - before) / 2: S0 goes 0.2 -> 0.6 -> 0.1.
 * Tick 1 has no previous value: 0.5. Tick 2: 0.5 + 0.4 / 2 = 0.7.
 * Tick 3: 0.5 - 0.5 / 2 = 0.25. */
TEST(sensor_derivative)
{
	mb_init(&b, 1, 1, 0);
	mb_copy(&b, "Master", 1, (uint8_t[]){EVO_IN_SD}, (uint16_t[]){0},
		(uint8_t[]){MO}, (uint16_t[]){0});
	CHECK_EQ_INT(mb_finish(&b), EVO_OK);
	evo_q16 act[1];
	mb_step(&b, (double[]){0.2}, act);
	CHECK_Q(act[0], 0.5);
	mb_step(&b, (double[]){0.6}, act);
	CHECK_Q(act[0], 0.7);
	mb_step(&b, (double[]){0.1}, act);
	CHECK_Q(act[0], 0.25);
}

/* A hard-coded skill under an influence of 0.5 sharing the wheels with the
 * master (which writes 0.5 to both, with influence 1):
 * TurnLeft writes left 0, right 1:
 * left = (1 * 0.5 + 0.5 * 0) / 1.5 = 1/3, right = (0.5 + 0.5) / 1.5 = 2/3. */
TEST(hardcoded_skill_blends_with_its_parent)
{
	mb_init(&b, 0, 2, 0);
	mb_const(&b, "Master", 3, (uint8_t[]){SK, MO, MO},
		 (uint16_t[]){1, 0, 1}, (double[]){0.5, 0.5, 0.5});
	mb_hardcoded(&b, "turnLeft", "TurnLeft", 2, (uint8_t[]){MO, MO},
		     (uint16_t[]){0, 1});
	CHECK_EQ_INT(mb_finish(&b), EVO_OK);
	evo_q16 act[2];
	mb_step(&b, NULL, act);
	CHECK_Q(act[0], 1.0 / 3);
	CHECK_Q(act[1], 2.0 / 3);
}

/* Outputs beyond [0, 1] are clamped before they are used. */
TEST(outputs_are_clamped)
{
	mb_init(&b, 0, 2, 0);
	mb_const(&b, "Master", 2, (uint8_t[]){MO, MO}, (uint16_t[]){0, 1},
		 (double[]){1.7, -0.4});
	CHECK_EQ_INT(mb_finish(&b), EVO_OK);
	evo_q16 act[2];
	mb_step(&b, NULL, act);
	CHECK_Q(act[0], 1.0);
	CHECK_Q(act[1], 0.0);
}

int main(void)
{
	RUN(chain);
	RUN(two_parents_share_a_child);
	RUN(shared_child_influence_clamps_to_one);
	RUN(skill_under_threshold_is_skipped_and_keeps_its_memory);
	RUN(threshold_edge);
	RUN(actuator_written_by_nobody_is_neutral);
	RUN(variable_written_by_two_skills);
	RUN(sensor_derivative);
	RUN(hardcoded_skill_blends_with_its_parent);
	RUN(outputs_are_clamped);
	return test_summary();
}
