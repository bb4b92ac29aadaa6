/* make bench: how fast the host reads CAN frames in each of its formats
 * (docs/can.md), on one core, beside the most frames a CAN bus can carry.
 *
 * slcan lines (core/src/wire.c, byte by byte as they come off a serial
 * line), cannelloni datagrams (one frame each, as evo sends them, and 32
 * each, as a cannelloni bridge aggregates them) and candump log lines, all
 * of evo's frames of 8 data bytes. The reference: a 1 Mbit/s bus carries
 * at most 1e6 / 111 = 9,009 such frames a second (an 8-byte frame with an
 * 11-bit id is 111 bits before stuffing). Each rate is the best of ROUNDS.
 * No bar: the issue asks for the figures; a decoder slower than the bus
 * would fail the comparison printed. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_proc.h"
#include "evo/wire.h"
#include "remote/can.h"

#define FRAMES 200000
#define ROUNDS 5
#define BUS_FRAMES 9009.0 /* 8-byte frames a second on a 1 Mbit/s bus */

static evo_can_frame frames[FRAMES];
static size_t len[FRAMES];	   /* each datagram's bytes */
static size_t starts[FRAMES + 1]; /* each log line's start */

static void make_frames(void)
{
	uint64_t s = 1;
	for (int i = 0; i < FRAMES; i++) {
		frames[i].id = (uint16_t)(0x100 + i % 64);
		frames[i].len = 8;
		for (int b = 0; b < 8; b++) {
			s = s * 6364136223846793005ull + 1442695040888963407ull;
			frames[i].data[b] = (uint8_t)(s >> 56);
		}
	}
}

static void report(const char *what, double best, size_t bytes)
{
	printf("  %-34s %10.0f frames/s  %6.1f MB/s  %7.0f x a 1 Mbit/s bus\n",
	       what, best, best * (double)bytes / FRAMES / 1e6,
	       best / BUS_FRAMES);
}

int main(void)
{
	make_frames();
	/* slcan: the whole stream, then fed byte by byte */
	size_t cap = (size_t)FRAMES * (EVO_SLCAN_LINE_MAX + 1);
	char *stream = malloc(cap);
	uint8_t *dgrams = malloc((size_t)FRAMES * 32);
	char *log = malloc((size_t)FRAMES * 64);
	if (!stream || !dgrams || !log)
		return 2;
	size_t n = 0;
	for (int i = 0; i < FRAMES; i++)
		n += evo_slcan_encode(&frames[i], stream + n);
	double best = 0;
	long got = 0;
	for (int r = 0; r < ROUNDS; r++) {
		evo_slcan_rx rx;
		evo_slcan_rx_init(&rx);
		evo_can_frame f;
		evo_wire_bad bad;
		got = 0;
		double t0 = bench_now();
		for (size_t i = 0; i < n; i++)
			got += evo_slcan_rx_byte(&rx, (uint8_t)stream[i], &f,
						 &bad) == EVO_SLCAN_FRAME;
		double rate = FRAMES / (bench_now() - t0);
		best = rate > best ? rate : best;
	}
	if (got != FRAMES) {
		fprintf(stderr, "bench_can: slcan decoded %ld of %d frames\n",
			got, FRAMES);
		return 1;
	}
	printf("Reading CAN frames of 8 bytes on one core, best of %d runs of "
	       "%d frames:\n",
	       ROUNDS, FRAMES);
	report("slcan lines, byte by byte", best, n);

	/* cannelloni: 1 and 32 frames a datagram */
	static const int per[2] = {1, 32};
	for (int p = 0; p < 2; p++) {
		size_t total = 0;
		int nd = 0;
		for (int i = 0; i < FRAMES; i += per[p]) {
			size_t l = evo_cannelloni_encode(
			    &frames[i], per[p], (uint8_t)nd, dgrams + total,
			    (size_t)FRAMES * 32 - total);
			len[nd++] = l;
			total += l;
		}
		best = 0;
		for (int r = 0; r < ROUNDS; r++) {
			evo_can_frame out[32];
			unsigned long bad[EVO_CAN_BAD_COUNT] = {0};
			int k;
			got = 0;
			size_t off = 0;
			double t0 = bench_now();
			for (int d = 0; d < nd; d++) {
				evo_cannelloni_decode(dgrams + off, len[d], out,
						      32, &k, bad);
				got += k;
				off += len[d];
			}
			double rate = FRAMES / (bench_now() - t0);
			best = rate > best ? rate : best;
		}
		if (got != FRAMES) {
			fprintf(stderr, "bench_can: cannelloni decoded %ld of %d "
					"frames\n",
				got, FRAMES);
			return 1;
		}
		char what[64];
		snprintf(what, sizeof what, "cannelloni, %d frame%s a datagram",
			 per[p], per[p] == 1 ? "" : "s");
		report(what, best, total);
	}

	/* candump lines */
	size_t ln = 0;
	for (int i = 0; i < FRAMES; i++) {
		starts[i] = ln;
		ln += evo_candump_format(&frames[i], 1436509052.249713 + i * 1e-4,
					 "can0", log + ln);
	}
	starts[FRAMES] = ln;
	best = 0;
	for (int r = 0; r < ROUNDS; r++) {
		got = 0;
		double t0 = bench_now();
		for (int i = 0; i < FRAMES; i++) {
			double t;
			char iface[EVO_CANDUMP_IFACE_MAX];
			evo_can_frame f;
			evo_can_bad why;
			got += evo_candump_parse(log + starts[i],
						 starts[i + 1] - starts[i] - 1,
						 &t, iface, &f, &why);
		}
		double rate = FRAMES / (bench_now() - t0);
		best = rate > best ? rate : best;
	}
	if (got != FRAMES) {
		fprintf(stderr, "bench_can: candump parsed %ld of %d lines\n",
			got, FRAMES);
		return 1;
	}
	report("candump log lines", best, ln);
	free(stream);
	free(dgrams);
	free(log);
	return 0;
}
