/* The mind image: written from a model, validated, run in place; anything
 * corrupt or mismatched refused with its reason. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/fileio.h"
#include "harness.h"
#include "support/cli.h"
#include "mind/mindfolder.h"
#include "support/rng.h"

#define TUTORIAL "tests/data/minds/T6-NEAT"

static evo_mindfolder *collect(void)
{
	evo_err err;
	evo_mindfolder_opts o = {.master = "Collect"};
	evo_mindfolder *l = evo_mindfolder_load(TUTORIAL, &o, &err);
	if (!l)
		printf("    %s\n", err.msg);
	return l;
}

/* Run a mind for ticks ticks on pseudo-random sensor values; fold every
 * actuator value and variable into a checksum, and keep the last ones. */
static uint32_t run(const evo_mind *m, int ticks, evo_q16 *last)
{
	size_t size = evo_state_size(m);
	void *mem = aligned_alloc(8, (size + 7) & ~(size_t)7);
	evo_state *s;
	if (evo_state_init(m, mem, size, &s) != EVO_OK) {
		free(mem);
		return 0;
	}
	rng r = rng_seed(42);
	uint32_t sum = 0;
	evo_q16 sensors[EVO_MAX_SENSORS], act[EVO_MAX_ACTUATORS];
	for (int t = 0; t < ticks; t++) {
		for (unsigned i = 0; i < m->n_sensors; i++)
			sensors[i] = (evo_q16)(rng_next(&r) % 65537);
		evo_mind_step(m, s, sensors, act);
		sum = evo_crc32(sum, act, sizeof act[0] * m->n_actuators);
		for (unsigned v = 0; v < m->n_vars; v++)
			sum = evo_crc32(sum, &s->var[v].value, 4);
	}
	memcpy(last, act, sizeof act[0] * m->n_actuators);
	free(mem);
	return sum;
}

/* Written to a file, read back into fresh memory, opened: the same
 * outputs, tick for tick, as the loaded model. */
TEST(image_round_trips_through_a_file)
{
	evo_mindfolder *l = collect();
	CHECK(l != NULL);
	if (!l)
		return;
	char path[600];
	snprintf(path, sizeof path, "%s/evo-test-image-%ld.bin",
		 cli_tmp_root(), (long)getpid());
	evo_err err;
	CHECK_EQ_INT(evo_write_file_atomic(path, l->image, l->image_len, &err),
		     0);
	char *data;
	size_t len;
	CHECK_EQ_INT(evo_read_file(path, &data, &len, &err), 0);
	unlink(path);
	CHECK_EQ_INT(len, l->image_len);
	void *copy = aligned_alloc(8, (len + 7) & ~(size_t)7);
	memcpy(copy, data, len);
	free(data);
	evo_mind m;
	CHECK_EQ_INT(evo_mind_open(copy, len, l->names_hash, &m), EVO_OK);
	evo_q16 a[EVO_MAX_ACTUATORS], b[EVO_MAX_ACTUATORS];
	uint32_t want = run(&l->mind, 2000, a);
	uint32_t got = run(&m, 2000, b);
	CHECK(want != 0);
	CHECK_EQ_INT(got, want);
	CHECK_EQ_INT(memcmp(a, b, sizeof a[0] * m.n_actuators), 0);
	/* The outputs move: a mind stuck at neutral would prove nothing. */
	CHECK(a[0] != EVO_Q16_HALF || a[1] != EVO_Q16_HALF);
	free(copy);
	evo_mindfolder_free(l);
}

/* The same model always writes the same bytes. */
TEST(image_is_reproducible)
{
	evo_mindfolder *a = collect(), *b = collect();
	CHECK(a && b);
	if (a && b) {
		CHECK_EQ_INT(a->image_len, b->image_len);
		CHECK_EQ_INT(memcmp(a->image, b->image, a->image_len), 0);
	}
	evo_mindfolder_free(a);
	evo_mindfolder_free(b);
}

TEST(flipped_byte_is_refused)
{
	evo_mindfolder *l = collect();
	if (!l) {
		CHECK(l != NULL);
		return;
	}
	uint8_t *img = l->image;
	evo_mind m;
	/* Every single byte, every bit: never opened. */
	unsigned opened = 0, crc = 0;
	for (size_t i = 0; i < l->image_len; i++)
		for (int bit = 0; bit < 8; bit++) {
			img[i] ^= (uint8_t)(1u << bit);
			evo_status st =
				evo_mind_open(img, l->image_len, l->names_hash,
					      &m);
			opened += st == EVO_OK;
			crc += st == EVO_ERR_IMAGE_CRC;
			img[i] ^= (uint8_t)(1u << bit);
		}
	CHECK_EQ_INT(opened, 0);
	/* Past the header's first 16 bytes, the CRC is what catches it. */
	CHECK(crc >= (l->image_len - 16) * 8 - 8 * 4);
	img[100] ^= 0x10;
	CHECK_EQ_INT(evo_mind_open(img, l->image_len, l->names_hash, &m),
		     EVO_ERR_IMAGE_CRC);
	CHECK_EQ_STR(evo_status_str(EVO_ERR_IMAGE_CRC),
		     "mind image is corrupt (CRC-32 mismatch)");
	img[100] ^= 0x10;
	img[0] ^= 1;
	CHECK_EQ_INT(evo_mind_open(img, l->image_len, l->names_hash, &m),
		     EVO_ERR_IMAGE_MAGIC);
	img[0] ^= 1;
	CHECK_EQ_INT(evo_mind_open(img, l->image_len, l->names_hash, &m),
		     EVO_OK);
	evo_mindfolder_free(l);
}

TEST(truncated_image_is_refused)
{
	evo_mindfolder *l = collect();
	if (!l) {
		CHECK(l != NULL);
		return;
	}
	evo_mind m;
	for (size_t cut = 0; cut < l->image_len; cut += 4)
		CHECK_EQ_INT(evo_mind_open(l->image, cut, l->names_hash, &m),
			     EVO_ERR_IMAGE_LENGTH);
	CHECK_EQ_STR(evo_status_str(EVO_ERR_IMAGE_LENGTH),
		     "mind image is truncated or has a bad length");
	evo_mindfolder_free(l);
}

/* An image built for another botdesc: one sensor renamed. */
TEST(image_for_another_botdesc_is_refused)
{
	evo_mindfolder *l = collect();
	if (!l) {
		CHECK(l != NULL);
		return;
	}
	evo_botdesc *other = malloc(sizeof *other);
	*other = *l->botdesc;
	snprintf(other->sensor[3].name, EVO_NAME_MAX, "US_4b");
	uint32_t other_hash = evo_names_hash_of(other, l->vardesc);
	CHECK(other_hash != l->names_hash);
	evo_mind m;
	CHECK_EQ_INT(evo_mind_open(l->image, l->image_len, other_hash, &m),
		     EVO_ERR_IMAGE_NAMES);
	/* Same names in another order are other sensors too. */
	*other = *l->botdesc;
	evo_botdesc_entry t = other->sensor[0];
	other->sensor[0] = other->sensor[1];
	other->sensor[1] = t;
	CHECK_EQ_INT(evo_mind_open(l->image, l->image_len,
				   evo_names_hash_of(other, l->vardesc), &m),
		     EVO_ERR_IMAGE_NAMES);
	CHECK_EQ_STR(evo_status_str(EVO_ERR_IMAGE_NAMES),
		     "mind image was built for other sensors, actuators or "
		     "variables");
	free(other);
	evo_mindfolder_free(l);
}

static void fix_crc(uint8_t *img)
{
	evo_image_header *h = (evo_image_header *)img;
	h->crc = evo_crc32(0, img + 16, h->length - 16);
}

/* A well-formed CRC does not make a bad layout acceptable. */
TEST(bad_layout_with_valid_crc_is_refused)
{
	evo_mindfolder *l = collect();
	if (!l) {
		CHECK(l != NULL);
		return;
	}
	uint8_t *img = malloc(l->image_len);
	evo_image_header *h = (evo_image_header *)img;
	evo_mind m;

	memcpy(img, l->image, l->image_len);
	h->version = 2;
	fix_crc(img);
	CHECK_EQ_INT(evo_mind_open(img, l->image_len, l->names_hash, &m),
		     EVO_ERR_IMAGE_VERSION);

	memcpy(img, l->image, l->image_len);
	h->off_io = h->length; /* io section past the end */
	fix_crc(img);
	CHECK_EQ_INT(evo_mind_open(img, l->image_len, l->names_hash, &m),
		     EVO_ERR_IMAGE_LAYOUT);

	/* A sub-skill pointing back up the hierarchy: a cycle. */
	memcpy(img, l->image, l->image_len);
	evo_image_io *io = (evo_image_io *)(img + h->off_io);
	evo_image_skill *sk = (evo_image_skill *)(img + h->off_skills);
	io[sk[1].out_start].index = 0;
	fix_crc(img);
	CHECK_EQ_INT(evo_mind_open(img, l->image_len, l->names_hash, &m),
		     EVO_ERR_IMAGE_LAYOUT);

	/* A hard-coded class this build does not have. */
	memcpy(img, l->image, l->image_len);
	sk[3].hc_class = evo_name_hash("Teleport");
	fix_crc(img);
	CHECK_EQ_INT(evo_mind_open(img, l->image_len, l->names_hash, &m),
		     EVO_ERR_IMAGE_CLASS);

	/* A sensor index out of range. */
	memcpy(img, l->image, l->image_len);
	io[sk[0].in_start].index = 200;
	fix_crc(img);
	CHECK_EQ_INT(evo_mind_open(img, l->image_len, l->names_hash, &m),
		     EVO_ERR_IMAGE_LAYOUT);

	/* Misaligned. */
	uint8_t *odd = malloc(l->image_len + 1);
	memcpy(odd + 1, l->image, l->image_len);
	CHECK_EQ_INT(evo_mind_open(odd + 1, l->image_len, l->names_hash, &m),
		     EVO_ERR_ALIGN);
	free(odd);
	free(img);
	evo_mindfolder_free(l);
}

/* A state needs the memory evo_state_size says, no less. */
TEST(state_memory_is_checked)
{
	evo_mindfolder *l = collect();
	if (!l) {
		CHECK(l != NULL);
		return;
	}
	size_t size = evo_state_size(&l->mind);
	void *mem = aligned_alloc(8, size + 8);
	evo_state *s;
	CHECK_EQ_INT(evo_state_init(&l->mind, mem, size - 1, &s),
		     EVO_ERR_NOMEM);
	CHECK_EQ_INT(evo_state_init(&l->mind, (char *)mem + 4, size, &s),
		     EVO_ERR_ALIGN);
	CHECK_EQ_INT(evo_state_init(&l->mind, mem, size, &s), EVO_OK);
	printf("    Collect example: image %zu bytes, state %zu bytes\n",
	       l->image_len, size);
	free(mem);
	evo_mindfolder_free(l);
}

TEST(crc32_matches_the_standard)
{
	/* The check value of CRC-32/ISO-HDLC. */
	CHECK_EQ_INT(evo_crc32(0, "123456789", 9), 0xCBF43926u);
	CHECK_EQ_INT(evo_crc32(evo_crc32(0, "1234", 4), "56789", 5),
		     0xCBF43926u);
}

TEST(hardcoded_class_hashes_are_distinct)
{
	for (unsigned i = 0; i < evo_hc_class_count; i++) {
		CHECK(evo_hc_find(evo_hc_classes[i].name) ==
		      &evo_hc_classes[i]);
		for (unsigned j = i + 1; j < evo_hc_class_count; j++)
			CHECK(evo_name_hash(evo_hc_classes[i].name) !=
			      evo_name_hash(evo_hc_classes[j].name));
	}
	CHECK(evo_hc_find("moveforward") == NULL);
}

int main(void)
{
	RUN(image_round_trips_through_a_file);
	RUN(image_is_reproducible);
	RUN(flipped_byte_is_refused);
	RUN(truncated_image_is_refused);
	RUN(image_for_another_botdesc_is_refused);
	RUN(bad_layout_with_valid_crc_is_refused);
	RUN(state_memory_is_checked);
	RUN(crc32_matches_the_standard);
	RUN(hardcoded_class_hashes_are_distinct);
	return test_summary();
}
