/* `evo flash`: a mind image to a running robot over CAN (cmd/flash.h). */
#define _POSIX_C_SOURCE 200809L
#include "cmd/flash.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "base/clock.h"
#include "base/fileio.h"
#include "evo/flash.h"
#include "evo/mind.h"
#include "mind/mindfolder.h"
#include "remote/can.h"

void evo_flash_usage(FILE *f)
{
	fputs("usage: evo flash MINDFOLDER|IMAGE.bin --can URL [--master "
	      "SKILL]\n"
	      "                 [--window N] [--wait MS] [--tries N]\n"
	      "                 [--key FILE] [--counter N] [--force]\n"
	      "  send the mind image to the robot's running firmware; URL is\n"
	      "  socketcan:IFACE, slcan:DEVICE, cannelloni:HOST:PORT, ...\n"
	      "  (docs/can.md); --key: the robot's key (docs/wire.md, Keys)\n",
	      f);
}

static int usage(void)
{
	evo_flash_usage(stderr);
	return 2;
}

static int whole(const char *opt, const char *v, long lo, long hi, long *out)
{
	char *end;
	long n = strtol(v, &end, 10);
	if (!*v || *end || n < lo || n > hi) {
		fprintf(stderr,
			"evo flash: %s expects a whole number from %ld to %ld, "
			"found '%s'\n",
			opt, lo, hi, v);
		return -1;
	}
	*out = n;
	return 0;
}

/* A key file: 32 to 128 hex digits (16 to 64 bytes), spaces and line
 * ends around them. The key is never printed, nor any part of the file. */
static int read_key(const char *path, uint8_t *key, size_t *len)
{
	FILE *in = fopen(path, "r");
	if (!in) {
		fprintf(stderr, "evo flash: --key %s: cannot read it: %s\n",
			path, strerror(errno));
		return -1;
	}
	size_t n = 0, digits = 0;
	int ch, hi = -1, bad = 0, done = 0;
	long line = 1;
	while ((ch = fgetc(in)) != EOF && !bad) {
		if (ch == '\n')
			line++;
		if (isspace(ch)) {
			done = digits > 0;
			continue;
		}
		int v = isdigit(ch)			  ? ch - '0'
			: (ch >= 'a' && ch <= 'f') ? ch - 'a' + 10
			: (ch >= 'A' && ch <= 'F') ? ch - 'A' + 10
						   : -1;
		if (v < 0 || done || digits >= 2 * EVO_FLASH_KEY_MAX) {
			bad = 1;
			break;
		}
		digits++;
		if (hi < 0) {
			hi = v;
		} else {
			key[n++] = (uint8_t)(hi << 4 | v);
			hi = -1;
		}
	}
	fclose(in);
	if (bad || digits % 2 || n < EVO_FLASH_KEY_MIN) {
		fprintf(stderr,
			"evo flash: --key %s:%ld: a key is %u to %u hex digits "
			"(%u to %u bytes) on one line, and nothing else; make "
			"one with: od -An -N32 -tx1 /dev/urandom | tr -d ' "
			"\\n' > FILE\n",
			path, line, 2 * EVO_FLASH_KEY_MIN,
			2 * EVO_FLASH_KEY_MAX, EVO_FLASH_KEY_MIN,
			EVO_FLASH_KEY_MAX);
		return -1;
	}
	*len = n;
	return 0;
}

/* Why the robot refused, with what the reply's detail says. */
static void print_refusal(const evo_flash_tx *t, uint32_t image_names)
{
	if (t->reason == EVO_FLASH_ERR_KEYED ||
	    t->reason == EVO_FLASH_ERR_UNKEYED) {
		fprintf(stderr,
			"evo flash: not sent: %s (%s); it keeps running the "
			"mind it had\n",
			evo_flash_reason_str(t->reason),
			t->reason == EVO_FLASH_ERR_KEYED
			    ? "give evo flash --key FILE"
			    : "build its firmware with make firmware "
			      "FW_KEY=FILE, or flash without --key");
		return;
	}
	fprintf(stderr, "evo flash: the robot refused the image: %s",
		evo_flash_reason_str(t->reason));
	uint32_t d = t->detail;
	switch (t->reason) {
	case EVO_FLASH_ERR_VERSION:
		fprintf(stderr, " (it speaks version %u, evo flash %u)", d,
			EVO_FLASH_VERSION);
		break;
	case EVO_FLASH_ERR_SIZE:
		fprintf(stderr, " (the image has %u bytes, the slot %u)",
			t->length, d);
		break;
	case EVO_FLASH_ERR_NAMES:
		fprintf(stderr,
			" (the image's names hash %08x, the robot's %08x)",
			image_names, d);
		break;
	case EVO_FLASH_ERR_INCOMPLETE:
		fprintf(stderr, " (%u of %u segments)", d, t->total);
		break;
	case EVO_FLASH_ERR_CRC:
		fprintf(stderr, " (the robot's %08x, the image's %08x)", d,
			t->crc);
		break;
	case EVO_FLASH_ERR_IMAGE:
		fprintf(stderr, ": %s", evo_status_str((evo_status)d));
		break;
	case EVO_FLASH_ERR_STATE:
		fprintf(stderr, " (%u bytes)", d);
		break;
	case EVO_FLASH_ERR_WRITE:
		fprintf(stderr, " (at byte %u)", d);
		break;
	case EVO_FLASH_ERR_TIMEOUT:
		fprintf(stderr, " (%u ms)", d);
		break;
	case EVO_FLASH_ERR_STALE:
		fprintf(stderr,
			" (the transfer's %u, the robot's %u; --counter N "
			"above it, or --force, sends it anyway)",
			t->counter, d);
		break;
	default:
		break;
	}
	fprintf(stderr, "; it keeps running the mind it had\n");
}

/* The image to send: a mind folder's, or an image file checked as the
 * robot will check it (but for the names, which only the robot knows). */
static int load_image(const char *path, const char *master, uint8_t **image,
		      size_t *len, char *name, size_t cap)
{
	evo_err err = {{0}};
	struct stat st;
	if (stat(path, &st) == 0 && S_ISREG(st.st_mode)) {
		char *data;
		if (evo_read_file(path, &data, len, &err) != 0) {
			fprintf(stderr, "%s\n", err.msg);
			return -1;
		}
		/* evo_mind_open needs 4-byte alignment: malloc gives it */
		uint8_t *img = malloc(*len ? *len : 1);
		if (!img) {
			free(data);
			fprintf(stderr, "evo flash: out of memory\n");
			return -1;
		}
		memcpy(img, data, *len);
		free(data);
		evo_mind m;
		evo_status s =
		    *len >= 20 ? evo_mind_open(img, *len,
					       evo_wire_get_u32(img + 16), &m)
			       : EVO_ERR_IMAGE_LENGTH;
		if (s != EVO_OK) {
			fprintf(stderr, "evo flash: %s: not sent: %s\n", path,
				evo_status_str(s));
			free(img);
			return -1;
		}
		snprintf(name, cap, "%s", evo_mind_skill_name(&m, 0));
		*image = img;
		return 0;
	}
	evo_mindfolder_opts opts = {0};
	opts.master = master;
	evo_mindfolder *l = evo_mindfolder_load(path, &opts, &err);
	if (!l) {
		fprintf(stderr, "%s\n", err.msg);
		return -1;
	}
	*image = malloc(l->image_len);
	if (!*image) {
		evo_mindfolder_free(l);
		fprintf(stderr, "evo flash: out of memory\n");
		return -1;
	}
	memcpy(*image, l->image, l->image_len);
	*len = l->image_len;
	snprintf(name, cap, "%s", evo_mind_skill_name(&l->mind, 0));
	evo_mindfolder_free(l);
	return 0;
}

/* Replies that answered nothing sent (forged, another transfer's, out of
 * turn), tags that did not verify, and the transport's own drops: said,
 * so that a forger on the bus does not go unnoticed. */
static void report_dropped(const evo_can *c, const evo_flash_tx *t,
			   const char *url)
{
	if (t->replies_dropped)
		fprintf(stderr,
			"evo flash: %s: ignored %u repl%s that answered "
			"nothing evo flash sent (late ones of a transfer begun "
			"again, another node on the bus, or a transfer "
			"replayed)\n",
			url, t->replies_dropped,
			t->replies_dropped == 1 ? "y" : "ies");
	if (t->tags_bad)
		fprintf(stderr,
			"evo flash: %s: ignored %u tag%s that were not made "
			"with the key given (another key, or a forger)\n",
			url, t->tags_bad, t->tags_bad == 1 ? "" : "s");
	const unsigned long *bad = evo_can_dropped(c);
	unsigned long total = 0;
	for (int i = 0; i < EVO_CAN_BAD_COUNT; i++)
		total += bad[i];
	if (!total)
		return;
	fprintf(stderr, "evo flash: %s: dropped %lu pieces of input that were "
			"no frames of evo's (",
		url, total);
	const char *sep = "";
	for (int i = 0; i < EVO_CAN_BAD_COUNT; i++)
		if (bad[i]) {
			fprintf(stderr, "%s%lu %s", sep, bad[i],
				evo_can_bad_name((evo_can_bad)i));
			sep = ", ";
		}
	fprintf(stderr, ")\n");
}

int evo_flash_main(int argc, char **argv)
{
	if (argc < 3)
		return usage();
	const char *path = argv[2], *url = NULL, *master = NULL;
	const char *key_path = NULL;
	long window = 16, wait_ms = 1000, tries = 5;
	long long counter = -1;
	int force = 0;
	for (int i = 3; i < argc; i++) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (strcmp(a, "--force") == 0) {
			force = 1;
			continue;
		}
		if (!v) {
			fprintf(stderr, "evo flash: %s needs a value\n", a);
			return usage();
		}
		i++;
		if (strcmp(a, "--can") == 0)
			url = v;
		else if (strcmp(a, "--master") == 0)
			master = v;
		else if (strcmp(a, "--window") == 0) {
			if (whole(a, v, 1, EVO_FLASH_WINDOW_MAX, &window))
				return 2;
		} else if (strcmp(a, "--wait") == 0) {
			if (whole(a, v, 10, 600000, &wait_ms))
				return 2;
		} else if (strcmp(a, "--tries") == 0) {
			if (whole(a, v, 1, 1000, &tries))
				return 2;
		} else if (strcmp(a, "--key") == 0) {
			key_path = v;
		} else if (strcmp(a, "--counter") == 0) {
			char *end;
			errno = 0;
			counter = strtoll(v, &end, 10);
			if (!*v || *end || errno || counter < 1 ||
			    counter > (long long)EVO_FLASH_COUNTER_MAX) {
				fprintf(stderr,
					"evo flash: --counter expects a whole "
					"number from 1 to %u, found '%s'\n",
					EVO_FLASH_COUNTER_MAX, v);
				return 2;
			}
		} else {
			fprintf(stderr, "evo flash: unexpected argument '%s'\n",
				a);
			return usage();
		}
	}
	if (!url) {
		fprintf(stderr, "evo flash: --can URL is required: the bus the "
				"robot is on (docs/can.md)\n");
		return usage();
	}
	uint8_t key[EVO_FLASH_KEY_MAX];
	size_t key_len = 0;
	if (key_path && read_key(key_path, key, &key_len) != 0)
		return 1;
	uint8_t *image;
	size_t len;
	char name[128];
	if (load_image(path, master, &image, &len, name, sizeof name) != 0)
		return 1;
	if (len > EVO_FLASH_LENGTH_MAX || len % 4) {
		fprintf(stderr,
			"evo flash: %s: the image has %zu bytes; a transfer "
			"carries a multiple of 4 up to %u\n",
			path, len, EVO_FLASH_LENGTH_MAX);
		free(image);
		return 1;
	}
	evo_err err = {{0}};
	evo_can *c = evo_can_open(url, &err);
	if (!c) {
		fprintf(stderr, "evo flash: %s\n", err.msg);
		free(image);
		return 1;
	}
	if (evo_can_pty_name(c))
		printf("evo flash: the robot's serial line is %s\n",
		       evo_can_pty_name(c));
	evo_flash_tx t;
	evo_flash_tx_init(&t, image, (uint32_t)len, (unsigned)window);
	if (key_len)
		evo_flash_tx_key(&t, key, key_len);
	if (counter > 0 || force)
		evo_flash_tx_counter(&t, counter > 0 ? (uint32_t)counter : 0u,
				     force);
	uint32_t names = evo_wire_get_u32(image + 16);
	printf("evo flash: mind %s, image %zu bytes in %u segments, to %s\n",
	       name, len, t.total, url);
	fflush(stdout);

	/* Send what the sender has, read replies; a try that brings no
	 * progress for wait_ms sends again what is not acknowledged, and
	 * `tries` of them in a row end it. */
	int rc = 1;
	double t0 = evo_clock_now(), try_start = t0;
	uint32_t progress = t.progress;
	long failed = 0;
	while (t.stage != EVO_FLASH_TX_FINISHED) {
		evo_can_frame f;
		while (evo_flash_tx_next(&t, &f))
			if (evo_can_send(c, &f, &err) != 0) {
				fprintf(stderr, "evo flash: %s\n", err.msg);
				goto out;
			}
		int r = evo_can_recv(c, 20, &f, &err);
		if (r < 0) {
			fprintf(stderr, "evo flash: %s\n", err.msg);
			goto out;
		}
		if (r == 1)
			evo_flash_tx_reply(&t, &f);
		double now = evo_clock_now();
		if (t.progress != progress) {
			progress = t.progress;
			failed = 0;
			try_start = now;
			continue;
		}
		if ((now - try_start) * 1000.0 < (double)wait_ms)
			continue;
		if (++failed >= tries) {
			if (t.stage == EVO_FLASH_TX_BEGIN)
				fprintf(stderr,
					"evo flash: no answer from the robot "
					"on %s (%ld tries of %ld ms): is it on "
					"the bus, and does its firmware take "
					"minds over it?\n",
					url, tries, wait_ms);
			else
				fprintf(stderr,
					"evo flash: the robot stopped "
					"answering after %u of %u segments "
					"(%ld tries of %ld ms): the transfer "
					"did not finish; the robot abandons "
					"it after its own timeout and keeps "
					"running the mind it had\n",
					t.acked, t.total, tries, wait_ms);
			goto out;
		}
		evo_flash_tx_timeout(&t);
		try_start = now;
	}
	if (t.kind == EVO_FLASH_DONE) {
		printf("evo flash: the robot runs mind %s from the tick after "
		       "%u (%u frames sent, %u segments sent again, %.2f s; "
		       "transfer counter %u)\n",
		       name, t.detail, t.frames, t.resent_segments,
		       evo_clock_now() - t0, t.counter);
		rc = 0;
	} else {
		print_refusal(&t, names);
	}
out:
	report_dropped(c, &t, url);
	evo_can_close(c);
	free(image);
	/* the key leaves no copy behind in this process's memory */
	memset(key, 0, sizeof key);
	return rc;
}
