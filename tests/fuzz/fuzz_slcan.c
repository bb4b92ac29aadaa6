/* libFuzzer target for the slcan decoder and the frame layout
 * (core/src/wire.c), which the firmware runs on every byte it receives.
 * Besides crashes and sanitizer reports it checks the decoder's promises:
 * a frame it returns has an 11-bit id and at most 8 bytes, encodes back to
 * a line that decodes to the same frame, and the receive state never
 * outgrows its line buffer; unpacking a frame never writes past the
 * values array. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "evo/wire.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define N_VALUES 21 /* odd: the last frame carries one value */

static void check_frame(const evo_can_frame *f)
{
	char line[EVO_SLCAN_LINE_MAX + 1];
	evo_can_frame g;
	evo_wire_bad bad = EVO_WIRE_BAD_COUNT;
	if (f->id > 0x7FF || f->len > 8)
		abort();
	size_t n = evo_slcan_encode(f, line);
	if (n != 6u + 2u * f->len || line[n - 1] != '\r')
		abort();
	if (evo_slcan_decode(line, n - 1, &g, &bad) != EVO_SLCAN_FRAME ||
	    g.id != f->id || g.len != f->len ||
	    memcmp(g.data, f->data, f->len) != 0)
		abort();
	/* Unpacking: values only at the frame's two slots, never past. */
	evo_q16 values[N_VALUES + 1];
	for (unsigned i = 0; i <= N_VALUES; i++)
		values[i] = 0x5A5A5A5A;
	int k = evo_wire_unpack(EVO_WIRE_SENSOR, f, values, N_VALUES);
	if (values[N_VALUES] != 0x5A5A5A5A)
		abort();
	if (k >= 0) {
		if ((unsigned)k >= evo_wire_frames(N_VALUES))
			abort();
		evo_can_frame p;
		evo_wire_pack(EVO_WIRE_SENSOR, values, N_VALUES, (unsigned)k,
			      &p);
		if (p.id != f->id || p.len != f->len ||
		    memcmp(p.data, f->data, f->len) != 0)
			abort();
	} else if (k != -1 - (int)EVO_WIRE_BAD_ID &&
		   k != -1 - (int)EVO_WIRE_BAD_LENGTH) {
		abort();
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	evo_slcan_rx rx;
	evo_can_frame f;
	evo_wire_bad bad;
	evo_slcan_rx_init(&rx);
	for (size_t i = 0; i < size; i++) {
		bad = EVO_WIRE_BAD_COUNT;
		switch (evo_slcan_rx_byte(&rx, data[i], &f, &bad)) {
		case EVO_SLCAN_FRAME:
			check_frame(&f);
			break;
		case EVO_SLCAN_BAD:
			if (bad >= EVO_WIRE_BAD_COUNT)
				abort();
			break;
		case EVO_SLCAN_MORE:
		case EVO_SLCAN_EMPTY:
			break;
		default:
			abort();
		}
		if (rx.n > EVO_SLCAN_LINE_MAX)
			abort();
	}
	/* The whole input as one line. */
	bad = EVO_WIRE_BAD_COUNT;
	evo_slcan_result r =
		evo_slcan_decode((const char *)data, size, &f, &bad);
	if (r == EVO_SLCAN_FRAME)
		check_frame(&f);
	else if (r == EVO_SLCAN_BAD && bad >= EVO_WIRE_BAD_COUNT)
		abort();
	else if (r == EVO_SLCAN_EMPTY && size != 0)
		abort();
	return 0;
}
