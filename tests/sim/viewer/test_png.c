/* evo's PNG writer and reader (sim/viewer/png.c) and the raster it saves
 * (sim/viewer/raster.c): images round-trip, the checksums match their published
 * values, damaged or foreign files are refused with a reason, and the
 * drawing primitives put pixels where their contracts say. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

#include "evo/image.h"
#include "harness.h"
#include "support/cli.h"
#include "viewer/png.h"
#include "viewer/raster.h"

#define PI 3.14159265358979323846

/* A pattern in which every byte differs from its neighbours, so a
 * shifted or swapped byte shows. */
static uint8_t *pattern(int w, int h, int ch)
{
	size_t n = (size_t)w * h * ch;
	uint8_t *p = malloc(n);
	for (size_t i = 0; i < n; i++)
		p[i] = (uint8_t)(i * 7 + i / 251);
	return p;
}

static uint32_t be32(const uint8_t *p)
{
	return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 |
	       (uint32_t)p[2] << 8 | p[3];
}

/* Rewrite the CRC of the chunk starting at `at` after editing it, so the
 * edit reaches the check behind the CRC. */
static void fix_crc(uint8_t *png, size_t at)
{
	uint32_t n = be32(png + at);
	uint32_t c = evo_png_crc32(0, png + at + 4, n + 4u);
	uint8_t *q = png + at + 8 + n;
	q[0] = (uint8_t)(c >> 24);
	q[1] = (uint8_t)(c >> 16);
	q[2] = (uint8_t)(c >> 8);
	q[3] = (uint8_t)c;
}

/* Signature 8 + IHDR 25: the IDAT chunk starts here. */
#define IDAT_AT 33

/* A copy of `png` (whose only IDAT starts at IDAT_AT) with the IDAT's data
 * replaced by `z`; its length in *out_len. */
static uint8_t *with_idat(const uint8_t *png, size_t len, const uint8_t *z,
			  size_t zlen, size_t *out_len)
{
	size_t old = be32(png + IDAT_AT), tail = len - (IDAT_AT + 12 + old);
	uint8_t *c = malloc(IDAT_AT + 12 + zlen + tail);
	memcpy(c, png, IDAT_AT);
	c[IDAT_AT] = (uint8_t)(zlen >> 24);
	c[IDAT_AT + 1] = (uint8_t)(zlen >> 16);
	c[IDAT_AT + 2] = (uint8_t)(zlen >> 8);
	c[IDAT_AT + 3] = (uint8_t)zlen;
	memcpy(c + IDAT_AT + 4, "IDAT", 4);
	memcpy(c + IDAT_AT + 8, z, zlen);
	fix_crc(c, IDAT_AT);
	memcpy(c + IDAT_AT + 12 + zlen, png + IDAT_AT + 12 + old, tail);
	*out_len = IDAT_AT + 12 + zlen + tail;
	return c;
}

/* `raw` (filtered rows) compressed by zlib; its length in *zlen. */
static uint8_t *deflated(const uint8_t *raw, size_t n, size_t *zlen)
{
	uLongf cap = compressBound((uLong)n);
	uint8_t *z = malloc(cap);
	CHECK_EQ_INT(compress(z, &cap, raw, (uLong)n), Z_OK);
	*zlen = cap;
	return z;
}

static int decode_fails_with(const uint8_t *png, size_t len, const char *want)
{
	evo_png_image img;
	evo_err err = {{0}};
	int rc = evo_png_decode(png, len, &img, &err);
	int ok = rc == -1 && img.pixels == NULL && strstr(err.msg, want);
	if (!ok)
		printf("    want an error with \"%s\", got rc %d: %s\n", want,
		       rc, err.msg);
	return ok;
}

TEST(checksums_match_their_published_values)
{
	CHECK_EQ_INT(evo_png_crc32(0, "123456789", 9), 0xCBF43926u);
	CHECK_EQ_INT(evo_png_crc32(0, "", 0), 0);
	/* In pieces, the same as in one go. */
	CHECK_EQ_INT(evo_png_crc32(evo_png_crc32(0, "1234", 4), "56789", 5),
		     0xCBF43926u);
	/* A long run of 0xFF bytes against core's bitwise CRC and zlib's. */
	size_t n = 100000;
	uint8_t *ff = malloc(n);
	memset(ff, 0xFF, n);
	CHECK_EQ_INT(evo_png_crc32(0, ff, n), evo_crc32(0, ff, n));
	CHECK_EQ_INT(evo_png_crc32(0, ff, n), (uint32_t)crc32(0, ff, (uInt)n));
	free(ff);
}

/* The file starts as a PNG must, with IHDR saying what was written. */
TEST(encoded_header_is_a_standard_png)
{
	uint8_t *px = pattern(3, 2, 3), *png;
	size_t len;
	evo_err err;
	CHECK_EQ_INT(evo_png_encode(px, 3, 2, 3, &png, &len, &err), 0);
	CHECK(memcmp(png, "\x89PNG\r\n\x1a\n", 8) == 0);
	CHECK_EQ_INT(be32(png + 8), 13);
	CHECK(memcmp(png + 12, "IHDR", 4) == 0);
	CHECK_EQ_INT(be32(png + 16), 3);
	CHECK_EQ_INT(be32(png + 20), 2);
	CHECK_EQ_INT(png[24], 8);
	CHECK_EQ_INT(png[25], 2);
	CHECK(memcmp(png + IDAT_AT + 4, "IDAT", 4) == 0);
	/* zlib's header: deflate, 32K window, the level field saying the
	 * fastest compression (png.c deflates with runs only, Z_RLE), and
	 * the two bytes a multiple of 31 as RFC 1950 wants. */
	CHECK_EQ_INT(png[IDAT_AT + 8], 0x78);
	CHECK_EQ_INT(png[IDAT_AT + 9], 0x01);
	CHECK_EQ_INT((png[IDAT_AT + 8] * 256 + png[IDAT_AT + 9]) % 31, 0);
	CHECK(memcmp(png + len - 12, "\0\0\0\0IEND\xae\x42\x60\x82", 12) == 0);
	free(png);
	free(px);
}

static void round_trip(int w, int h, int ch)
{
	uint8_t *px = pattern(w, h, ch), *png;
	size_t len;
	evo_err err;
	evo_png_image img;
	CHECK_EQ_INT(evo_png_encode(px, w, h, ch, &png, &len, &err), 0);
	CHECK_EQ_INT(evo_png_decode(png, len, &img, &err), 0);
	CHECK_EQ_INT(img.w, w);
	CHECK_EQ_INT(img.h, h);
	CHECK_EQ_INT(img.channels, ch);
	CHECK(img.pixels && memcmp(img.pixels, px, (size_t)w * h * ch) == 0);
	evo_png_image_free(&img);
	free(png);
	free(px);
}

TEST(images_round_trip_in_memory)
{
	round_trip(1, 1, 3);
	round_trip(1, 1, 4);
	round_trip(17, 5, 3);
	round_trip(9, 13, 4);
	/* Patterns deflate cannot shrink much, over several blocks. */
	round_trip(200, 120, 3);
	round_trip(428, 102, 3);
}

/* A learning curve's worth of one colour with a few lines packs into a
 * small fraction of its raw size. */
TEST(plain_images_are_compressed)
{
	int w = 800, h = 500;
	uint8_t *px = malloc((size_t)w * h * 3), *png;
	memset(px, 0xFF, (size_t)w * h * 3);
	for (int x = 0; x < w; x++)
		memset(px + ((size_t)(h / 2 + x % 40) * w + x) * 3, 0x20, 3);
	size_t len;
	evo_err err;
	CHECK_EQ_INT(evo_png_encode(px, w, h, 3, &png, &len, &err), 0);
	CHECK(len < (size_t)w * h * 3 / 50);
	evo_png_image img;
	CHECK_EQ_INT(evo_png_decode(png, len, &img, &err), 0);
	CHECK(img.pixels && memcmp(img.pixels, px, (size_t)w * h * 3) == 0);
	evo_png_image_free(&img);
	free(png);
	free(px);
}

/* An image of n colours (colour c is red c % 256, green c / 256, blue
 * 0x80, so all differ) in a pattern where neighbours differ. */
static uint8_t *coloured(int w, int h, int n)
{
	uint8_t *p = malloc((size_t)w * h * 3);
	for (int i = 0; i < w * h; i++) {
		int c = (i * 7 + i / 13) % n;
		p[3 * i] = (uint8_t)(c % 256);
		p[3 * i + 1] = (uint8_t)(c / 256);
		p[3 * i + 2] = 0x80;
	}
	return p;
}

/* Encoded with the palette writer: the header's bit depth and colour
 * type, and the pixels decoded back unchanged. */
static void palette_round_trip(int w, int h, int n, int depth, int ctype)
{
	uint8_t *px = coloured(w, h, n), *png;
	size_t len;
	evo_err err;
	evo_png_image img;
	CHECK_EQ_INT(evo_png_encode_indexed(px, w, h, &png, &len, &err), 0);
	CHECK_EQ_INT(png[24], depth);
	CHECK_EQ_INT(png[25], ctype);
	if (ctype == 3) {
		CHECK(memcmp(png + IDAT_AT + 4, "PLTE", 4) == 0);
		CHECK_EQ_INT(be32(png + IDAT_AT), 3 * n);
		/* colours in the order they first appear */
		CHECK(memcmp(png + IDAT_AT + 8, px, 6) == 0);
	}
	CHECK_EQ_INT(evo_png_decode(png, len, &img, &err), 0);
	CHECK_EQ_INT(img.w, w);
	CHECK_EQ_INT(img.h, h);
	CHECK_EQ_INT(img.channels, 3);
	CHECK(img.pixels && memcmp(img.pixels, px, (size_t)w * h * 3) == 0);
	evo_png_image_free(&img);
	free(png);
	free(px);
}

/* A few colours take the fewest bits PNG allows a palette index (1, 2, 4
 * or 8); past 256 colours the image stays RGB. Widths that leave part of
 * a row's last byte unused come back whole. */
TEST(few_colours_are_written_as_a_palette)
{
	palette_round_trip(13, 3, 2, 1, 3);
	palette_round_trip(9, 4, 3, 2, 3);
	palette_round_trip(4, 4, 4, 2, 3);
	palette_round_trip(7, 5, 5, 4, 3);
	palette_round_trip(31, 9, 17, 8, 3);
	palette_round_trip(128, 16, 256, 8, 3);
	palette_round_trip(128, 16, 257, 8, 2);
	/* runs of every length from 1 to 11 pixels, so a colour changes at
	 * every offset into the 8 bytes the writer compares at a time */
	int rw = 61, rh = 7;
	uint8_t *runs = malloc((size_t)rw * rh * 3);
	for (int i = 0, c = 0, left = 1, len = 1; i < rw * rh; i++) {
		runs[3 * i] = (uint8_t)(c * 40);
		runs[3 * i + 1] = (uint8_t)(255 - c * 40);
		runs[3 * i + 2] = (uint8_t)c;
		if (--left == 0) {
			c = (c + 1) % 5;
			len = len % 11 + 1;
			left = len;
		}
	}
	uint8_t *rpng;
	size_t rlen;
	evo_err rerr;
	evo_png_image rimg;
	CHECK_EQ_INT(evo_png_encode_indexed(runs, rw, rh, &rpng, &rlen, &rerr),
		     0);
	CHECK_EQ_INT(rpng[24], 4);
	CHECK_EQ_INT(evo_png_decode(rpng, rlen, &rimg, &rerr), 0);
	CHECK(rimg.pixels &&
	      memcmp(rimg.pixels, runs, (size_t)rw * rh * 3) == 0);
	evo_png_image_free(&rimg);
	free(rpng);
	free(runs);
	/* one colour: 1 bit a pixel, a one-entry palette */
	uint8_t px[5 * 3], *png;
	memset(px, 0x7F, sizeof px);
	size_t len;
	evo_err err;
	CHECK_EQ_INT(evo_png_encode_indexed(px, 5, 1, &png, &len, &err), 0);
	CHECK_EQ_INT(png[24], 1);
	CHECK_EQ_INT(be32(png + IDAT_AT), 3);
	evo_png_image img;
	CHECK_EQ_INT(evo_png_decode(png, len, &img, &err), 0);
	CHECK(img.pixels && memcmp(img.pixels, px, sizeof px) == 0);
	evo_png_image_free(&img);
	free(png);
}

/* A palette file put together byte by byte here (not by evo's writer):
 * 3 x 2 pixels, 2 bits each, palette red, green, blue; row 0 holds
 * indices 0 1 2 (bits 00 01 10 00 = 0x18), row 1 indices 2 2 0 (10 10 00
 * 00 = 0xA0). An index past the palette is refused. */
TEST(a_hand_made_palette_file_decodes)
{
	uint8_t raw[] = {0, 0x18, 0, 0xA0};
	size_t zlen;
	uint8_t *z = deflated(raw, sizeof raw, &zlen);
	uint8_t f[200], *p = f;
	memcpy(p, "\x89PNG\r\n\x1a\n", 8);
	p += 8;
	static const uint8_t ihdr[] = {0, 0, 0, 13, 'I', 'H', 'D', 'R', 0, 0, 0,
				       3, 0, 0, 0,  2,	 2,   3,   0,	0, 0};
	memcpy(p, ihdr, sizeof ihdr);
	p += sizeof ihdr + 4;
	fix_crc(f, 8);
	size_t plte_at = (size_t)(p - f);
	static const uint8_t plte[] = {0, 0, 0, 9,   'P', 'L', 'T', 'E', 255,
				       0, 0, 0, 255, 0,	  0,   0,   255};
	memcpy(p, plte, sizeof plte);
	p += sizeof plte + 4;
	fix_crc(f, plte_at);
	size_t idat_at = (size_t)(p - f);
	p[0] = p[1] = p[2] = 0;
	p[3] = (uint8_t)zlen;
	memcpy(p + 4, "IDAT", 4);
	memcpy(p + 8, z, zlen);
	p += 12 + zlen;
	fix_crc(f, idat_at);
	memcpy(p, "\0\0\0\0IEND\xae\x42\x60\x82", 12);
	p += 12;
	evo_png_image img;
	evo_err err;
	CHECK_EQ_INT(evo_png_decode(f, (size_t)(p - f), &img, &err), 0);
	static const uint8_t want[] = {255, 0, 0,   0, 255, 0,	 0,   0, 255,
				       0,   0, 255, 0, 0,   255, 255, 0, 0};
	CHECK_EQ_INT(img.channels, 3);
	CHECK(img.pixels && memcmp(img.pixels, want, sizeof want) == 0);
	evo_png_image_free(&img);
	/* index 3 of a 3-colour palette */
	raw[1] = 0x1C;
	free(z);
	z = deflated(raw, sizeof raw, &zlen);
	memcpy(f + idat_at + 8, z, zlen);
	fix_crc(f, idat_at);
	CHECK(decode_fails_with(f, (size_t)(p - f),
				"row 0 has a palette index past the palette's "
				"3 colours"));
	free(z);
}

TEST(a_file_round_trips_and_is_replaced_whole)
{
	char dir[512];
	snprintf(dir, sizeof dir, "%s/evo-test-png-XXXXXX", cli_tmp_root());
	CHECK(mkdtemp(dir) != NULL);
	char path[600];
	snprintf(path, sizeof path, "%s/img.png", dir);
	evo_err err;
	uint8_t *a = pattern(31, 7, 4), *b = pattern(8, 8, 3);
	CHECK_EQ_INT(evo_png_write(path, a, 31, 7, 4, &err), 0);
	CHECK_EQ_INT(evo_png_write(path, b, 8, 8, 3, &err), 0);
	evo_png_image img;
	CHECK_EQ_INT(evo_png_read(path, &img, &err), 0);
	CHECK_EQ_INT(img.w, 8);
	CHECK_EQ_INT(img.channels, 3);
	CHECK(img.pixels && memcmp(img.pixels, b, 8 * 8 * 3) == 0);
	evo_png_image_free(&img);
	free(a);
	free(b);
	/* A missing file names itself. */
	char missing[600];
	snprintf(missing, sizeof missing, "%s/none.png", dir);
	CHECK_EQ_INT(evo_png_read(missing, &img, &err), -1);
	CHECK_CONTAINS(err.msg, "none.png");
	unlink(path);
	rmdir(dir);
}

TEST(bad_shapes_are_refused_by_the_writer)
{
	uint8_t px[12] = {0}, *png = (uint8_t *)1;
	size_t len = 1;
	evo_err err;
	CHECK_EQ_INT(evo_png_encode(px, 0, 1, 3, &png, &len, &err), -1);
	CHECK_CONTAINS(err.msg, "0 x 1");
	CHECK(png == NULL && len == 0);
	CHECK_EQ_INT(evo_png_encode(px, 2, 2, 2, &png, &len, &err), -1);
	CHECK_CONTAINS(err.msg, "2 channels");
	CHECK_EQ_INT(
	    evo_png_encode(px, 1, EVO_PNG_MAX_SIDE + 1, 3, &png, &len, &err),
	    -1);
	CHECK_EQ_INT(evo_png_write("/nonexistent-dir/x.png", px, 2, 2, 3, &err),
		     -1);
	CHECK_CONTAINS(err.msg, "/nonexistent-dir/x.png");
}

/* Every truncation and every flipped bit of a small file is refused:
 * the signature, the lengths and every chunk's CRC leave nowhere for
 * damage to hide. */
TEST(every_damaged_copy_is_refused)
{
	uint8_t *px = pattern(5, 4, 3), *png;
	size_t len;
	evo_err err;
	CHECK_EQ_INT(evo_png_encode(px, 5, 4, 3, &png, &len, &err), 0);
	int accepted = 0;
	for (size_t cut = 0; cut < len; cut++) {
		evo_png_image img;
		if (evo_png_decode(png, cut, &img, &err) == 0) {
			accepted++;
			evo_png_image_free(&img);
		}
	}
	CHECK_EQ_INT(accepted, 0);
	uint8_t *copy = malloc(len);
	for (size_t bit = 0; bit < len * 8; bit++) {
		memcpy(copy, png, len);
		copy[bit / 8] ^= (uint8_t)(1u << bit % 8);
		evo_png_image img;
		err.msg[0] = 0;
		if (evo_png_decode(copy, len, &img, &err) == 0) {
			accepted++;
			evo_png_image_free(&img);
		} else if (!err.msg[0]) {
			accepted++; /* refused without a reason */
		}
	}
	CHECK_EQ_INT(accepted, 0);
	free(copy);
	free(png);
	free(px);
}

TEST(damage_is_named)
{
	uint8_t *px = pattern(4, 3, 3), *png;
	size_t len;
	evo_err err;
	CHECK_EQ_INT(evo_png_encode(px, 4, 3, 3, &png, &len, &err), 0);
	uint8_t *c = malloc(len + 32);

	CHECK(decode_fails_with(png, 4, "not a PNG"));
	CHECK(decode_fails_with(png, len - 1, "no IEND"));

	memcpy(c, png, len);
	c[IDAT_AT + 8 + 5] ^= 1; /* a byte of the zlib stream */
	CHECK(
	    decode_fails_with(c, len, "chunk 1 (IDAT) at byte 33 is damaged"));
	fix_crc(c, IDAT_AT);
	CHECK(decode_fails_with(c, len, "image data is damaged: zlib: "));

	/* The stream against the header: rows of 4 x 3 RGB pixels are
	 * 3 x 13 bytes with their filter bytes. */
	uint8_t raw[3 * 13 + 1];
	for (int y = 0; y < 3; y++) {
		raw[y * 13] = 0;
		memcpy(raw + y * 13 + 1, px + y * 12, 12);
	}
	raw[39] = 0;
	size_t zlen, dn;
	uint8_t *z = deflated(raw, 40, &zlen), *d;
	d = with_idat(png, len, z, zlen, &dn);
	CHECK(decode_fails_with(d, dn, "longer than the 39 bytes"));
	free(d);
	free(z);
	z = deflated(raw, 38, &zlen);
	d = with_idat(png, len, z, zlen, &dn);
	CHECK(decode_fails_with(d, dn,
				"image data has 38 bytes, its header "
				"implies 39"));
	free(d);
	/* Cut off inside the stream, and bytes after its end. */
	free(z);
	z = deflated(raw, 39, &zlen);
	d = with_idat(png, len, z, zlen - 6, &dn);
	CHECK(decode_fails_with(d, dn, "cut off"));
	free(d);
	uint8_t *z2 = malloc(zlen + 2);
	memcpy(z2, z, zlen);
	z2[zlen] = z2[zlen + 1] = 0;
	d = with_idat(png, len, z2, zlen + 2, &dn);
	CHECK(decode_fails_with(d, dn, "2 bytes after its end"));
	free(d);
	free(z2);
	free(z);

	/* A row filter other than None. */
	raw[13] = 1; /* row 1's filter byte */
	z = deflated(raw, 39, &zlen);
	d = with_idat(png, len, z, zlen, &dn);
	CHECK(decode_fails_with(d, dn, "row 1 uses filter type 1"));
	free(d);
	free(z);

	/* 16 bits per sample; a palette image; interlaced. */
	memcpy(c, png, len);
	c[24] = 16;
	fix_crc(c, 8);
	CHECK(decode_fails_with(c, len, "16 bits per sample"));
	memcpy(c, png, len);
	c[25] = 3;
	fix_crc(c, 8);
	CHECK(decode_fails_with(c, len, "palette image without a PLTE"));
	memcpy(c, png, len);
	c[25] = 4; /* grey with alpha */
	fix_crc(c, 8);
	CHECK(decode_fails_with(c, len, "colour type 4"));
	memcpy(c, png, len);
	c[28] = 1;
	fix_crc(c, 8);
	CHECK(decode_fails_with(c, len, "interlace method 1"));

	/* A header announcing a huge image over a few bytes of data is
	 * refused before anything of that size is allocated. */
	memcpy(c, png, len);
	c[18] = 0x40; /* width and height 0x4000 = 16384 */
	c[19] = 0;
	c[22] = 0x40;
	c[23] = 0;
	fix_crc(c, 8);
	CHECK(decode_fails_with(c, len, "fewer than deflate needs"));

	/* Trailing bytes after IEND. */
	memcpy(c, png, len);
	c[len] = 0;
	CHECK(decode_fails_with(c, len + 1, "1 bytes after IEND"));

	/* An ancillary chunk is skipped; an unknown critical one is not. */
	static const char text[] = "tEXtComment\0hello";
	for (int critical = 0; critical < 2; critical++) {
		size_t n = sizeof text - 1 - 4, at = IDAT_AT;
		memcpy(c, png, at);
		c[at] = 0;
		c[at + 1] = 0;
		c[at + 2] = 0;
		c[at + 3] = (uint8_t)n;
		memcpy(c + at + 4, text, n + 4);
		if (critical)
			c[at + 4] = 'T';
		fix_crc(c, at);
		memcpy(c + at + 12 + n, png + at, len - at);
		evo_png_image img;
		int rc = evo_png_decode(c, len + 12 + n, &img, &err);
		if (critical) {
			CHECK_EQ_INT(rc, -1);
			CHECK_CONTAINS(err.msg, "critical chunk TEXt");
		} else {
			CHECK_EQ_INT(rc, 0);
			CHECK(img.pixels && !memcmp(img.pixels, px, 36));
			evo_png_image_free(&img);
		}
	}
	free(c);
	free(png);
	free(px);
}

/* ---- raster --------------------------------------------------------- */

static int count(const evo_raster *im, uint32_t rgb)
{
	int n = 0;
	for (int y = 0; y < im->h; y++)
		for (int x = 0; x < im->w; x++)
			n += evo_raster_get(im, x, y) == rgb;
	return n;
}

TEST(pixels_rects_and_blending)
{
	evo_raster im;
	evo_err err;
	CHECK_EQ_INT(evo_raster_init(&im, 0, 5, &err), -1);
	CHECK_CONTAINS(err.msg, "0 x 5");
	CHECK_EQ_INT(evo_raster_init(&im, 40, 30, &err), 0);
	CHECK_EQ_INT(count(&im, 0x000000), 1200);
	evo_raster_clear(&im, 0x102030);
	CHECK_EQ_INT(evo_raster_get(&im, 39, 29), 0x102030);
	CHECK_EQ_INT(im.pixels[0], 0x10);
	CHECK_EQ_INT(im.pixels[2], 0x30);
	evo_raster_pixel(&im, 3, 4, 0xFF0000, 255);
	CHECK_EQ_INT(evo_raster_get(&im, 3, 4), 0xFF0000);
	CHECK_EQ_INT(im.pixels[3 * (4 * 40 + 3)], 0xFF);
	/* Off the image: nothing happens (ASan would see a stray write). */
	evo_raster_pixel(&im, -1, 0, 0xFFFFFF, 255);
	evo_raster_pixel(&im, 40, 0, 0xFFFFFF, 255);
	evo_raster_fill_rect(&im, -100, -100, 1000000, 5, 0xFFFFFF, 255);
	CHECK_EQ_INT(count(&im, 0xFFFFFF), 0);
	evo_raster_fill_rect(&im, 10, 10, 5, 3, 0x00FF00, 255);
	CHECK_EQ_INT(count(&im, 0x00FF00), 15);
	CHECK_EQ_INT(evo_raster_get(&im, 10, 10), 0x00FF00);
	CHECK_EQ_INT(evo_raster_get(&im, 14, 12), 0x00FF00);
	CHECK_EQ_INT(evo_raster_get(&im, 15, 12), 0x102030);
	evo_raster_rect(&im, 20, 5, 6, 4, 0x0000FF, 255);
	CHECK_EQ_INT(count(&im, 0x0000FF), 16);
	CHECK_EQ_INT(evo_raster_get(&im, 22, 6), 0x102030);
	/* Half-way blend of white over black, rounded. */
	evo_raster_fill_rect(&im, 0, 20, 2, 2, 0x000000, 255);
	evo_raster_fill_rect(&im, 0, 20, 2, 2, 0xFFFFFF, 128);
	CHECK_EQ_INT(evo_raster_get(&im, 1, 21), 0x808080);
	evo_raster_pixel(&im, 0, 20, 0xFFFFFF, 0);
	CHECK_EQ_INT(evo_raster_get(&im, 0, 20), 0x808080);
	evo_raster_free(&im);
	CHECK(im.pixels == NULL);
	evo_raster_free(&im);
}

TEST(lines_run_between_their_ends)
{
	evo_raster im;
	evo_err err;
	CHECK_EQ_INT(evo_raster_init(&im, 50, 50, &err), 0);
	evo_raster_line(&im, 5, 5, 25, 5, 0xFF0000, 255);
	CHECK_EQ_INT(count(&im, 0xFF0000), 21);
	evo_raster_line(&im, 2, 10, 12, 20, 0x00FF00, 255);
	CHECK_EQ_INT(count(&im, 0x00FF00), 11);
	for (int k = 0; k <= 10; k++)
		CHECK_EQ_INT(evo_raster_get(&im, 2 + k, 10 + k), 0x00FF00);
	/* A steep line has one pixel per row. */
	evo_raster_line(&im, 40, 2, 43, 30, 0x0000FF, 255);
	CHECK_EQ_INT(count(&im, 0x0000FF), 29);
	CHECK_EQ_INT(evo_raster_get(&im, 40, 2), 0x0000FF);
	CHECK_EQ_INT(evo_raster_get(&im, 43, 30), 0x0000FF);
	/* From far off the image: only the visible part, quickly. */
	evo_raster_line(&im, -2000000000, 45, 2000000000, 45, 0xFFFF00, 255);
	CHECK_EQ_INT(count(&im, 0xFFFF00), 50);
	evo_raster_line(&im, -10, -10, -5, 60, 0xFFFFFF, 255);
	CHECK_EQ_INT(count(&im, 0xFFFFFF), 0);
	/* A thick horizontal line covers width rows. */
	evo_raster_clear(&im, 0);
	evo_raster_thick_line(&im, 10, 20, 30, 20, 4, 0xFF00FF, 255);
	CHECK_EQ_INT(evo_raster_get(&im, 20, 18), 0xFF00FF);
	CHECK_EQ_INT(evo_raster_get(&im, 20, 21), 0xFF00FF);
	CHECK_EQ_INT(evo_raster_get(&im, 20, 22), 0);
	CHECK_EQ_INT(evo_raster_get(&im, 20, 17), 0);
	CHECK_EQ_INT(count(&im, 0xFF00FF), 4 * 24);
	evo_raster_free(&im);
}

TEST(circles_and_polygons_cover_their_area)
{
	evo_raster im;
	evo_err err;
	CHECK_EQ_INT(evo_raster_init(&im, 100, 100, &err), 0);
	evo_raster_fill_circle(&im, 50, 50, 20, 0xFF0000, 255);
	int n = count(&im, 0xFF0000);
	CHECK(fabs(n - PI * 400) < 40);
	CHECK_EQ_INT(evo_raster_get(&im, 50, 50), 0xFF0000);
	CHECK_EQ_INT(evo_raster_get(&im, 50, 30), 0xFF0000);
	CHECK_EQ_INT(evo_raster_get(&im, 50, 29), 0);
	CHECK_EQ_INT(evo_raster_get(&im, 71, 50), 0);
	/* A ring 3 wide: the outer disc less the inner one. */
	evo_raster_circle(&im, 50, 50, 20, 3, 0x00FF00, 255);
	int ring = count(&im, 0x00FF00);
	CHECK(fabs(ring - PI * (400 - 289)) < 30);
	CHECK_EQ_INT(evo_raster_get(&im, 50, 50), 0xFF0000);
	CHECK_EQ_INT(evo_raster_get(&im, 50, 31), 0x00FF00);
	CHECK_EQ_INT(count(&im, 0xFF0000) + ring, n);

	/* An axis-aligned square of side 10 on pixel edges: 100 pixels;
	 * the same square turned 45 degrees: about 100 too. */
	evo_raster_clear(&im, 0);
	double x[4] = {10, 20, 20, 10}, y[4] = {10, 10, 20, 20};
	evo_raster_fill_polygon(&im, x, y, 4, 0x0000FF, 255);
	CHECK_EQ_INT(count(&im, 0x0000FF), 100);
	CHECK_EQ_INT(evo_raster_get(&im, 19, 19), 0x0000FF);
	CHECK_EQ_INT(evo_raster_get(&im, 20, 19), 0);
	double r = 10 / sqrt(2.0);
	/* (Off the pixel lattice: centred on a pixel corner, its edges
	 * would pass through rows of pixel centres.) */
	double dx[4] = {60.3, 60.3 + r, 60.3, 60.3 - r},
	       dy[4] = {60.2 - r, 60.2, 60.2 + r, 60.2};
	evo_raster_fill_polygon(&im, dx, dy, 4, 0xFFFFFF, 255);
	n = count(&im, 0xFFFFFF);
	CHECK(abs(n - 100) <= 6);
	CHECK_EQ_INT(evo_raster_get(&im, 60, 60), 0xFFFFFF);
	/* Its outline passes through the corners. */
	evo_raster_polygon(&im, x, y, 4, 0x00FFFF, 255);
	CHECK_EQ_INT(evo_raster_get(&im, 10, 10), 0x00FFFF);
	CHECK_EQ_INT(evo_raster_get(&im, 20, 15), 0x00FFFF);
	/* Not-a-number and far-away shapes draw nothing and do not
	 * crash. */
	double bad[4] = {NAN, 1, 2, 3};
	evo_raster_fill_polygon(&im, bad, y, 4, 0xFFFF00, 255);
	evo_raster_fill_circle(&im, 1e300, 0, 5, 0xFFFF00, 255);
	evo_raster_fill_circle(&im, 50, 50, INFINITY, 0xFFFF00, 255);
	CHECK_EQ_INT(count(&im, 0xFFFF00), 0);
	evo_raster_free(&im);
}

/* Every printable character has ink but the space; the bitmap is what
 * the text drawing puts down. */
TEST(text_draws_its_glyphs)
{
	for (int c = 33; c <= 126; c++) {
		const uint8_t *g = evo_font_glyph((unsigned char)c);
		int ink = 0;
		for (int r = 0; r < EVO_FONT_H; r++) {
			ink |= g[r];
			CHECK(g[r] < 32); /* 5 columns */
		}
		if (!ink)
			printf("    '%c' has no ink\n", c);
		CHECK(ink);
	}
	const uint8_t *sp = evo_font_glyph(' ');
	for (int r = 0; r < EVO_FONT_H; r++)
		CHECK_EQ_INT(sp[r], 0);
	/* Distinct glyphs for characters that are easy to confuse. */
	CHECK(memcmp(evo_font_glyph('0'), evo_font_glyph('O'), 7) != 0);
	CHECK(memcmp(evo_font_glyph('1'), evo_font_glyph('l'), 7) != 0);
	CHECK(memcmp(evo_font_glyph('1'), evo_font_glyph('I'), 7) != 0);
	/* A byte outside 32-126 draws as a box, not as nothing. */
	CHECK_EQ_INT(evo_font_glyph(200)[0], 0x1F);
	CHECK_EQ_INT(evo_font_glyph('\t')[3], 0x11);

	evo_raster im;
	evo_err err;
	CHECK_EQ_INT(evo_raster_init(&im, 64, 32, &err), 0);
	CHECK_EQ_INT(evo_raster_text(&im, 2, 3, "Hi", 0xFFFFFF, 1), 12);
	/* 'H' is 7 + 7 + 3 pixels; 'i' 1 + 2 + 1 + 1 + 1 + 3. */
	CHECK_EQ_INT(count(&im, 0xFFFFFF), 17 + 9);
	/* 'H''s top-left and bottom-left are ink, its top middle is not. */
	CHECK_EQ_INT(evo_raster_get(&im, 2, 3), 0xFFFFFF);
	CHECK_EQ_INT(evo_raster_get(&im, 2, 9), 0xFFFFFF);
	CHECK_EQ_INT(evo_raster_get(&im, 4, 3), 0);
	CHECK_EQ_INT(evo_raster_get(&im, 4, 6), 0xFFFFFF);
	/* At scale 2 every pixel becomes 2 x 2. */
	evo_raster_clear(&im, 0);
	CHECK_EQ_INT(evo_raster_text(&im, 0, 0, "H", 0xFFFFFF, 2), 12);
	CHECK_EQ_INT(count(&im, 0xFFFFFF), 17 * 4);
	CHECK_EQ_INT(evo_raster_text_width("ab\nlonger", 1), 6 * 6);
	CHECK_EQ_INT(evo_raster_text_height("ab\nlonger", 2), 2 * 9 * 2);
	CHECK_EQ_INT(evo_raster_text_width("", 3), 0);
	/* Text running off the image is clipped; scales are clamped to
	 * [1, 64], and pens far off the image do not overflow. */
	evo_raster_text(&im, 60, 28, "WWWW", 0xFFFFFF, 3);
	evo_raster_text(&im, -10, -5, "gjpqy", 0xFFFFFF, 1);
	CHECK_EQ_INT(evo_raster_text(&im, 0, 0, "W", 0xFFFFFF, 1000000),
		     6 * 64);
	CHECK_EQ_INT(evo_raster_text_width("W", -3), 6);
	CHECK_EQ_INT(evo_raster_text(&im, 2147483000, 2147483000, "WWW\nW",
				     0xFFFFFF, 64),
		     3 * 6 * 64);
	evo_raster_free(&im);
}

/* What the raster saves, the reader gives back, byte for byte. */
TEST(a_drawing_saves_as_png)
{
	char dir[512];
	snprintf(dir, sizeof dir, "%s/evo-test-png-XXXXXX", cli_tmp_root());
	CHECK(mkdtemp(dir) != NULL);
	char path[600];
	snprintf(path, sizeof path, "%s/curve.png", dir);
	evo_raster im;
	evo_err err;
	CHECK_EQ_INT(evo_raster_init(&im, 320, 200, &err), 0);
	evo_raster_clear(&im, 0xFFFFFF);
	evo_raster_text(&im, 10, 10, "fitness", 0x000000, 2);
	for (int i = 0; i < 30; i++)
		evo_raster_thick_line(&im, 10 + i * 10, 190 - i * 5,
				      20 + i * 10, 185 - i * 5, 2, 0x2060C0,
				      255);
	CHECK_EQ_INT(evo_raster_save_png(&im, path, &err), 0);
	evo_png_image img;
	CHECK_EQ_INT(evo_png_read(path, &img, &err), 0);
	CHECK_EQ_INT(img.w, 320);
	CHECK_EQ_INT(img.h, 200);
	CHECK_EQ_INT(img.channels, 3);
	CHECK(img.pixels && !memcmp(img.pixels, im.pixels, 320 * 200 * 3));
	evo_png_image_free(&img);
	evo_raster_free(&im);
	unlink(path);
	rmdir(dir);
}

int main(void)
{
	RUN(checksums_match_their_published_values);
	RUN(encoded_header_is_a_standard_png);
	RUN(images_round_trip_in_memory);
	RUN(plain_images_are_compressed);
	RUN(few_colours_are_written_as_a_palette);
	RUN(a_hand_made_palette_file_decodes);
	RUN(a_file_round_trips_and_is_replaced_whole);
	RUN(bad_shapes_are_refused_by_the_writer);
	RUN(every_damaged_copy_is_refused);
	RUN(damage_is_named);
	RUN(pixels_rects_and_blending);
	RUN(lines_run_between_their_ends);
	RUN(circles_and_polygons_cover_their_area);
	RUN(text_draws_its_glyphs);
	RUN(a_drawing_saves_as_png);
	return test_summary();
}
