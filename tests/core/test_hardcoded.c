/* Hard-coded skills (core/src/hardcoded.c). The tick finds a class by the
 * hash written in its row; the host by its name. The two must agree. */
#include <stdio.h>

#include "evo/mind.h"
#include "harness.h"

/* Each row's written-out hash is evo_name_hash of its name: the image
 * stores that hash, and the tick looks it up. */
TEST(every_class_is_found_by_the_hash_of_its_name)
{
	for (unsigned i = 0; i < evo_hc_class_count; i++) {
		const char *name = evo_hc_classes[i].name;
		const evo_hc_class *c = evo_hc_find_hash(evo_name_hash(name));
		if (c != &evo_hc_classes[i])
			printf("    row %s: its hash should be 0x%08Xu\n", name,
			       (unsigned)evo_name_hash(name));
		CHECK(c == &evo_hc_classes[i]);
		CHECK(evo_hc_find(name) == &evo_hc_classes[i]);
	}
	CHECK(evo_hc_find_hash(evo_name_hash("Teleport")) == NULL);
	CHECK(evo_hc_find("Teleport") == NULL);
}

/* Outputs are MO:left-wheel, MO:right-wheel: 0 back, 0.5 still, 1 on. */
TEST(wheel_classes_write_their_two_commands)
{
	static const struct {
		const char *name;
		evo_q16 left, right;
	} want[] = {
		{"MoveForward", EVO_Q16_ONE, EVO_Q16_ONE},
		{"MoveBackwards", 0, 0},
		{"TurnLeft", 0, EVO_Q16_ONE},
		{"TurnRight", EVO_Q16_ONE, 0},
		{"Stop", EVO_Q16_HALF, EVO_Q16_HALF},
	};
	for (unsigned i = 0; i < sizeof want / sizeof want[0]; i++) {
		const evo_hc_class *c = evo_hc_find(want[i].name);
		CHECK(c != NULL);
		if (!c)
			continue;
		CHECK_EQ_INT(c->n_in, -1);
		CHECK_EQ_INT(c->n_out, 2);
		evo_q16 out[2] = {-1, -1};
		int32_t mem[EVO_HC_WORDS] = {0};
		evo_hc_ctx ctx = {.out = out, .n_out = 2, .mem = mem};
		c->fn(&ctx);
		CHECK_EQ_INT(out[0], want[i].left);
		CHECK_EQ_INT(out[1], want[i].right);
	}
}

int main(void)
{
	RUN(every_class_is_found_by_the_hash_of_its_name);
	RUN(wheel_classes_write_their_two_commands);
	return test_summary();
}
