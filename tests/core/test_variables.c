/* Variables (core/src/variables.c; docs/mind.md, "Variables"). */
#include <math.h>

#include "harness.h"
#include "support/minibuild.h"
#include "variables.h"

static minibuild b;

static const uint8_t VA = EVO_OUT_VA, SK = EVO_OUT_SK;

static double val(unsigned v)
{
	return evo_q16_to_double(b.state->var[v].value);
}

/* A mind where the master copies sensor S0 to SK:Writer, and Writer
 * writes sensor S1 to variable V0: S0 = 1 writes S1, S0 = 0 leaves V0
 * unwritten that tick. */
static void writer_mind(uint8_t type)
{
	mb_init(&b, 2, 0, 1);
	b.var_type[0] = type;
	mb_copy(&b, "Master", 1, (uint8_t[]){EVO_IN_SE}, (uint16_t[]){0},
		(uint8_t[]){SK}, (uint16_t[]){1});
	mb_copy(&b, "Writer", 1, (uint8_t[]){EVO_IN_SE}, (uint16_t[]){1},
		(uint8_t[]){VA}, (uint16_t[]){0});
	CHECK_EQ_INT(mb_finish(&b), EVO_OK);
}

static void write(double level)
{
	mb_step(&b, (double[]){1.0, level}, NULL);
}

static void idle(void)
{
	mb_step(&b, (double[]){0.0, 0.0}, NULL);
}

TEST(plain_variable_starts_at_zero_and_keeps_what_was_written)
{
	writer_mind(EVO_VAR_PLAIN);
	CHECK_EQ_INT(b.state->var[0].value, 0);
	write(0.75);
	CHECK_EQ_INT(b.state->var[0].value, 49152);
	idle();
	idle();
	CHECK_EQ_INT(b.state->var[0].value, 49152);
	write(0.25);
	CHECK_EQ_INT(b.state->var[0].value, 16384);
}

/* The sine, at a million phases spread over the turn and around each
 * quadrant's start, folded into a CRC-32: the values of the plain-table
 * code this replaced (checked equal to it at all 2^32 phases when the
 * table was compressed). A change here changes every sin variable. */
TEST(sin_is_pinned)
{
	uint32_t crc = 0;
	for (uint64_t p = 0; p < (1ull << 32); p += 4093) {
		evo_q16 y = evo_var_sin01((uint32_t)p);
		crc = evo_crc32(crc, &y, sizeof y);
	}
	for (uint32_t q = 0; q < 4; q++)
		for (uint32_t d = 0; d < 3; d++) {
			evo_q16 y = evo_var_sin01((q << 30) + d - 1);
			crc = evo_crc32(crc, &y, sizeof y);
		}
	CHECK_EQ_INT(crc, 0xC2828C41u);
	CHECK_EQ_INT(evo_var_sin01(0), EVO_Q16_HALF);
	CHECK_EQ_INT(evo_var_sin01(1u << 30), EVO_Q16_ONE);
	CHECK_EQ_INT(evo_var_sin01(3u << 30), 0);
}

/* Unwritten, it reads (sin t + 1) / 2 at tick t. */
TEST(sin_variable_follows_the_tick)
{
	writer_mind(EVO_VAR_SINWAVE);
	double worst = 0;
	for (int t = 0; t <= 5000; t++) {
		double want = (sin((double)t) + 1) / 2;
		double d = fabs(val(0) - want);
		if (d > worst)
			worst = d;
		idle();
	}
	printf("    sin variable, 5000 ticks: max error %.2e\n", worst);
	CHECK(worst < 2e-4);
}

/* Written 0.0 the step is 1/1000 rad a tick, written 1.0 it is 3 rad;
 * the step stays when nobody writes. */
TEST(sin_variable_frequency_follows_what_is_written)
{
	writer_mind(EVO_VAR_SINWAVE);
	write(0.0); /* phase 0.001 after this tick */
	CHECK(fabs(val(0) - (sin(0.001) + 1) / 2) < 1e-4);
	for (int t = 0; t < 999; t++)
		idle();
	CHECK(fabs(val(0) - (sin(1.0) + 1) / 2) < 2e-4);

	writer_mind(EVO_VAR_SINWAVE);
	write(1.0);
	CHECK(fabs(val(0) - (sin(3.0) + 1) / 2) < 1e-4);
	idle();
	CHECK(fabs(val(0) - (sin(6.0) + 1) / 2) < 1e-4);

	writer_mind(EVO_VAR_SINWAVE);
	write(0.5); /* 0.001 + 0.5 * 2.999 = 1.5005 rad a tick */
	idle();
	CHECK(fabs(val(0) - (sin(2 * 1.5005) + 1) / 2) < 1e-4);
}

TEST(counter_counts_rising_edges_above_0_8)
{
	writer_mind(EVO_VAR_COUNTER);
	CHECK_EQ_INT(b.state->var[0].value, 0);
	write(0.81); /* 0.5 -> 0.81: rising edge */
	CHECK_EQ_INT(b.state->var[0].value, 6554);
	write(0.95); /* still high: no edge */
	CHECK_EQ_INT(b.state->var[0].value, 6554);
	write(0.5);
	write(0.8); /* exactly 0.8 is not above 0.8 */
	CHECK_EQ_INT(b.state->var[0].value, 6554);
	write(0.9); /* 0.8 -> 0.9 crosses */
	CHECK_EQ_INT(b.state->var[0].value, 13107);
	idle(); /* unwritten: holds, and the level it remembers stays high */
	write(0.9);
	CHECK_EQ_INT(b.state->var[0].value, 13107);
}

TEST(counter_resets_on_falling_edge_below_0_2)
{
	writer_mind(EVO_VAR_COUNTER);
	write(0.9);
	write(0.5);
	write(0.9);
	CHECK_EQ_INT(b.state->var[0].value, 13107); /* 0.2 */
	write(0.2); /* exactly 0.2 is not under 0.2 */
	CHECK_EQ_INT(b.state->var[0].value, 13107);
	write(0.9);
	CHECK_EQ_INT(b.state->var[0].value, 19661); /* 0.3 */
	write(0.19);
	CHECK_EQ_INT(b.state->var[0].value, 0);
	write(0.1); /* already low: no edge, stays 0 */
	CHECK_EQ_INT(b.state->var[0].value, 0);
}

/* Exactly count * 65536 / 10 rounded to nearest, for every count. */
TEST(counter_reads_tenths_and_wraps_past_ten)
{
	writer_mind(EVO_VAR_COUNTER);
	for (int i = 1; i <= 12; i++) {
		int count = i % 11;
		write(0.9);
		CHECK_EQ_INT(b.state->var[0].value,
			     (int32_t)floor(count * 65536 / 10.0 + 0.5));
		write(0.5);
	}
}

/* VD reads 0.5 + change / 2 of the variable's value since last tick. */
TEST(variable_derivative)
{
	mb_init(&b, 1, 1, 1);
	/* Master: reads VD:V0, copies it to M0, and writes S0 to V0. */
	unsigned m = mb_copy(&b, "Master", 2,
			     (uint8_t[]){EVO_IN_VD, EVO_IN_SE},
			     (uint16_t[]){0, 0},
			     (uint8_t[]){EVO_OUT_MO, EVO_OUT_VA},
			     (uint16_t[]){0, 0});
	(void)m;
	CHECK_EQ_INT(mb_finish(&b), EVO_OK);
	evo_q16 act[1];
	mb_step(&b, (double[]){0.4}, act); /* V0 0 -> 0.4 at the end */
	CHECK(fabs(evo_q16_to_double(act[0]) - 0.5) < 1e-4);
	mb_step(&b, (double[]){0.3}, act); /* reads 0.4 - 0 */
	CHECK(fabs(evo_q16_to_double(act[0]) - 0.7) < 1e-4);
	mb_step(&b, (double[]){0.3}, act); /* reads 0.3 - 0.4 */
	CHECK(fabs(evo_q16_to_double(act[0]) - 0.45) < 1e-4);
	mb_step(&b, (double[]){0.3}, act); /* reads 0.3 - 0.3 */
	CHECK(fabs(evo_q16_to_double(act[0]) - 0.5) < 1e-4);
}

TEST(reset_restores_tick_zero)
{
	writer_mind(EVO_VAR_COUNTER);
	write(0.9);
	CHECK_EQ_INT(b.state->tick, 1);
	evo_state_reset(&b.mind, b.state);
	CHECK_EQ_INT(b.state->tick, 0);
	CHECK_EQ_INT(b.state->var[0].value, 0);
	write(0.9); /* the remembered level is back to 0.5: an edge */
	CHECK_EQ_INT(b.state->var[0].value, 6554);
}

int main(void)
{
	RUN(sin_is_pinned);
	RUN(plain_variable_starts_at_zero_and_keeps_what_was_written);
	RUN(sin_variable_follows_the_tick);
	RUN(sin_variable_frequency_follows_what_is_written);
	RUN(counter_counts_rising_edges_above_0_8);
	RUN(counter_resets_on_falling_edge_below_0_2);
	RUN(counter_reads_tenths_and_wraps_past_ten);
	RUN(variable_derivative);
	RUN(reset_restores_tick_zero);
	return test_summary();
}
