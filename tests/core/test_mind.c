/* evo_mind_open (core/src/mind.c) on network weights and biases: an image
 * whose weight or bias reaches EVO_NET_WEIGHT_MAX is refused with
 * EVO_ERR_IMAGE_RANGE, since the argument that a network's sums cannot
 * overflow rests on that bound (docs/fixed-point.md); values one ulp
 * inside it open and run.
 *
 * The images are built, then patched behind a repaired CRC, the way a
 * buggy tool or a hostile sender could write them. Run with
 * EVO_WRITE_IMAGES=DIR, this test also writes the two refused images to
 * DIR (tests/data/images/README.md: the fuzzer's seeds). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "support/minibuild.h"

static minibuild b;

/* Largest magnitude allowed, in Q16: one ulp inside the exclusive limit. */
#define LIM ((evo_q16)(EVO_NET_WEIGHT_MAX * EVO_Q16_ONE))

/* The master's network: node 100 (bias 100) reads itself and node 101,
 * and node 101 copies node 100. Node 100 has the two links; with both
 * weights near 2^31 its sum overflows 64 bits by the third tick, which is
 * what the range check prevents. */
static void build(void)
{
	static const uint8_t MO = EVO_OUT_MO;
	mb_init(&b, 1, 1, 0);
	unsigned i = mb_counter(&b, "M", 100.0, MO, 0);
	evo_netdesc *d = &b.net[i];
	d->node[d->n_nodes++] = (evo_netdesc_node){
		.id = 101, .act = EVO_ACT_IDENTITY, .bias = 0};
	d->link[d->n_links++] =
		(evo_netdesc_link){.from = 101, .to = 100, .weight = 65536};
	d->link[d->n_links++] =
		(evo_netdesc_link){.from = 100, .to = 101, .weight = 65536};
}

/* The compiled network of the master, inside b.image. */
static evo_net_node *master_nodes(void)
{
	return (evo_net_node *)(b.image + b.mind.net[0].off_nodes);
}

static evo_net_link *master_links(void)
{
	return (evo_net_link *)(b.image + b.mind.net[0].off_links);
}

static evo_net_node *two_link_node(void)
{
	evo_net_node *n = master_nodes();
	unsigned count = b.mind.net[0].n_nodes - b.mind.net[0].n_in;
	for (unsigned k = 0; k < count; k++)
		if (n[k].link_count == 2)
			return &n[k];
	return NULL;
}

/* Repair the CRC after a patch and open the image again. */
static evo_status reopen(void)
{
	evo_image_header *h = (evo_image_header *)b.image;
	h->crc = evo_crc32(0, b.image + 16, b.image_len - 16);
	evo_mind m;
	uint32_t hash = evo_names_hash(b.sensor, b.n_sensors, b.actuator,
				       b.n_actuators, b.var, b.n_vars);
	return evo_mind_open(b.image, b.image_len, hash, &m);
}

/* Build, then set both weights into node 100 to w. */
static evo_status with_weights(evo_q16 w)
{
	build();
	if (mb_finish(&b) != EVO_OK)
		return EVO_STATUS_COUNT;
	evo_net_node *n = two_link_node();
	if (!n)
		return EVO_STATUS_COUNT;
	master_links()[n->link_start].weight = w;
	master_links()[n->link_start + 1].weight = w;
	return reopen();
}

/* Build, then set node 100's bias to v. */
static evo_status with_bias(evo_q16 v)
{
	build();
	if (mb_finish(&b) != EVO_OK)
		return EVO_STATUS_COUNT;
	evo_net_node *n = two_link_node();
	if (!n)
		return EVO_STATUS_COUNT;
	n->bias = v;
	return reopen();
}

static void write_image(const char *name)
{
	const char *dir = getenv("EVO_WRITE_IMAGES");
	if (!dir)
		return;
	char path[512];
	snprintf(path, sizeof path, "%s/%s", dir, name);
	FILE *f = fopen(path, "wb");
	CHECK(f != NULL);
	if (!f)
		return;
	CHECK(fwrite(b.image, 1, b.image_len, f) == b.image_len);
	fclose(f);
}

TEST(built_image_opens)
{
	build();
	CHECK_EQ_INT(mb_finish(&b), EVO_OK);
	CHECK(two_link_node() != NULL);
}

TEST(weight_out_of_range_is_refused)
{
	CHECK_EQ_INT(with_weights(LIM), EVO_ERR_IMAGE_RANGE);
	CHECK_EQ_INT(with_weights(-LIM), EVO_ERR_IMAGE_RANGE);
	CHECK_EQ_INT(with_weights(INT32_MIN), EVO_ERR_IMAGE_RANGE);
	CHECK_EQ_INT(with_weights(INT32_MAX), EVO_ERR_IMAGE_RANGE);
	write_image("out-of-range-weight.bin");
	CHECK_EQ_STR(evo_status_str(EVO_ERR_IMAGE_RANGE),
		     "mind image has a network weight or bias out of range");
}

TEST(bias_out_of_range_is_refused)
{
	CHECK_EQ_INT(with_bias(LIM), EVO_ERR_IMAGE_RANGE);
	CHECK_EQ_INT(with_bias(INT32_MIN), EVO_ERR_IMAGE_RANGE);
	CHECK_EQ_INT(with_bias(-LIM), EVO_ERR_IMAGE_RANGE);
	write_image("out-of-range-bias.bin");
}

/* One ulp inside the limit opens, and a few ticks of the largest weights
 * on saturated activations stay within 64 bits (UBSan in test-asan would
 * report an overflow). */
TEST(boundary_values_open_and_run)
{
	CHECK_EQ_INT(with_bias(LIM - 1), EVO_OK);
	CHECK_EQ_INT(with_bias(-(LIM - 1)), EVO_OK);
	CHECK_EQ_INT(with_weights(-(LIM - 1)), EVO_OK);
	CHECK_EQ_INT(with_weights(LIM - 1), EVO_OK);
	evo_mind m;
	evo_state *s;
	uint32_t hash = evo_names_hash(b.sensor, b.n_sensors, b.actuator,
				       b.n_actuators, b.var, b.n_vars);
	CHECK_EQ_INT(evo_mind_open(b.image, b.image_len, hash, &m), EVO_OK);
	CHECK_EQ_INT(evo_state_init(&m, b.state_mem, sizeof b.state_mem, &s),
		     EVO_OK);
	evo_q16 sensors[1] = {0}, act[1];
	for (int t = 0; t < 4; t++)
		evo_mind_step(&m, s, sensors, act);
	CHECK_EQ_INT(act[0], EVO_Q16_ONE); /* saturated, clamped to 1 */
}

int main(void)
{
	RUN(built_image_opens);
	RUN(weight_out_of_range_is_refused);
	RUN(bias_out_of_range_is_refused);
	RUN(boundary_values_open_and_run);
	return test_summary();
}
