/* libFuzzer target for the host's slcan reader (sim/remote/can_format.c:
 * evo_slcan_read), which takes what an adapter or a peer writes on a
 * serial line or a pseudo-terminal. The first byte picks the role (the
 * program that drives an adapter, or the adapter a peer drives) and where
 * the rest is cut in two. Besides crashes and sanitizer reports it checks
 * the reader's promises: every frame taken is a classic frame with an
 * 11-bit id, the answers stay within their buffer, and what comes in one
 * read or in two gives the same frames, drops and answers. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "remote/can.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define MAX 64

typedef struct outcome {
	evo_can_frame f[2 * MAX];
	int n;
	unsigned long bad[EVO_CAN_BAD_COUNT];
	char reply[256];
	size_t reply_len;
} outcome;

static outcome one, two;

static void feed(outcome *o, evo_slcan_reader *r, const char *b, size_t n)
{
	int got = 0;
	evo_slcan_read(r, b, n, o->f + o->n, MAX, &got, o->bad, o->reply,
		       sizeof o->reply, &o->reply_len);
	if (got < 0 || got > MAX || o->reply_len > sizeof o->reply)
		abort();
	for (int i = 0; i < got; i++)
		if (o->f[o->n + i].id > 0x7FF || o->f[o->n + i].len > 8)
			abort();
	o->n += got;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 1)
		return 0;
	const char *b = (const char *)data + 1;
	size_t n = size - 1;
	if (n > MAX * 4)
		n = MAX * 4; /* so that one read's frames fit in MAX */
	size_t cut = n ? (size_t)data[0] % (n + 1) : 0;
	int adapter = data[0] & 1;
	memset(&one, 0, sizeof one);
	memset(&two, 0, sizeof two);
	evo_slcan_reader r1 = {.as_adapter = adapter},
			 r2 = {.as_adapter = adapter};
	feed(&one, &r1, b, n);
	feed(&two, &r2, b, cut);
	feed(&two, &r2, b + cut, n - cut);
	if (one.n != two.n || memcmp(one.f, two.f, sizeof one.f[0] * one.n) ||
	    memcmp(one.bad, two.bad, sizeof one.bad) ||
	    one.reply_len != two.reply_len ||
	    memcmp(one.reply, two.reply, one.reply_len))
		abort();
	return 0;
}
