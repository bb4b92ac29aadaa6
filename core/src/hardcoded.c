/* Built-in hard-coded skills, found by the name a .ades gives after class:.
 *
 * To add one in C:
 *   1. write a function `static void my_skill(evo_hc_ctx *c)` below that
 *      reads c->in[0 .. n_in-1] and writes c->out[0 .. n_out-1] (Q16,
 *      clamped to [0, 1] by the caller); c->mem gives EVO_HC_WORDS words
 *      that persist across ticks and are zero after a reset;
 *   2. add a row X("MySkill", hash, n_in, n_out, my_skill) to HC_CLASSES,
 *      with -1 for a count the skill does not constrain, and hash
 *      evo_name_hash("MySkill") written out (tests/core/test_hardcoded
 *      checks every hash and prints the right one);
 *   3. rebuild. The mind loader refuses a .ades whose counts do not fit.
 * A mind image names its classes by evo_name_hash(name), so rows may be
 * added or reordered without invalidating images; a renamed class does
 * invalidate them (the image is refused with EVO_ERR_IMAGE_CLASS).
 *
 * One list makes two tables: evo_hc_classes, with the names, for the host,
 * and evo_hc_table, with the hashes, for the tick. A firmware links only the
 * second, so it carries neither the names nor a string hash.
 * docs/mind.md, Hard-coded skills, lists the classes. */
#include "hardcoded.h"

#define FULL_FORWARD EVO_Q16_ONE
#define FULL_BACK 0
#define STILL EVO_Q16_HALF

/* The two-wheeled robot's movements: outputs are MO:left-wheel,
 * MO:right-wheel in that order, each 0.0 full back, 0.5 still, 1.0 full
 * forward. */
static void wheels(evo_hc_ctx *c, evo_q16 left, evo_q16 right)
{
	c->out[0] = left;
	c->out[1] = right;
}

static void move_forward(evo_hc_ctx *c)
{
	wheels(c, FULL_FORWARD, FULL_FORWARD);
}

static void move_backwards(evo_hc_ctx *c)
{
	wheels(c, FULL_BACK, FULL_BACK);
}

static void turn_left(evo_hc_ctx *c)
{
	wheels(c, FULL_BACK, FULL_FORWARD);
}

static void turn_right(evo_hc_ctx *c)
{
	wheels(c, FULL_FORWARD, FULL_BACK);
}

static void stop(evo_hc_ctx *c)
{
	wheels(c, STILL, STILL);
}

#define HC_CLASSES(X)                                                          \
	X("MoveForward", 0x869A64D9u, -1, 2, move_forward)                     \
	X("MoveBackwards", 0xF45868EAu, -1, 2, move_backwards)                 \
	X("TurnLeft", 0xA837A0D7u, -1, 2, turn_left)                           \
	X("TurnRight", 0x5AB6F648u, -1, 2, turn_right)                         \
	X("Stop", 0x4B7F7705u, -1, 2, stop)

const evo_hc_class evo_hc_classes[] = {
#define HOST_ROW(name, hash, n_in, n_out, fn) {name, n_in, n_out, fn},
	HC_CLASSES(HOST_ROW)
#undef HOST_ROW
};

const unsigned evo_hc_class_count =
	sizeof evo_hc_classes / sizeof evo_hc_classes[0];

const evo_hc_row evo_hc_table[] = {
#define TICK_ROW(name, hash, n_in, n_out, fn) {hash, n_in, n_out, fn},
	HC_CLASSES(TICK_ROW)
#undef TICK_ROW
};

int evo_hc_index_of(uint32_t hash)
{
	for (unsigned i = 0; i < sizeof evo_hc_table / sizeof evo_hc_table[0];
	     i++)
		if (evo_hc_table[i].hash == hash)
			return (int)i;
	return -1;
}

const evo_hc_class *evo_hc_find_hash(uint32_t hash)
{
	int i = evo_hc_index_of(hash);
	return i < 0 ? NULL : &evo_hc_classes[i];
}

static int same_name(const char *a, const char *b)
{
	while (*a && *a == *b) {
		a++;
		b++;
	}
	return *a == *b;
}

const evo_hc_class *evo_hc_find(const char *name)
{
	for (unsigned i = 0; i < evo_hc_class_count; i++)
		if (same_name(evo_hc_classes[i].name, name))
			return &evo_hc_classes[i];
	return NULL;
}
