/* PNG through zlib: see png.h.
 *
 * A file is the signature, IHDR, a PLTE for a palette image, one IDAT
 * holding the zlib stream, IEND.
 * The stream holds the rows, each after its filter byte 0 (None): a
 * learning curve or a screenshot is mostly runs of one colour, which
 * deflate packs well without a row filter. */
#include "viewer/png.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "base/fileio.h"

static const uint8_t signature[8] = {0x89, 'P',	 'N',  'G',
				     '\r', '\n', 0x1A, '\n'};

/* ---- checksums ------------------------------------------------------ */

/* CRC-32 of every 4-bit value (reflected polynomial 0xEDB88320): two
 * lookups a byte, about four times faster than going bit by bit, and a
 * const table needs no first-use initialisation that threads could
 * race on. */
static const uint32_t crc_nibble[16] = {
    0x00000000, 0x1DB71064, 0x3B6E20C8, 0x26D930AC, 0x76DC4190, 0x6B6B51F4,
    0x4DB26158, 0x5005713C, 0xEDB88320, 0xF00F9344, 0xD6D6A3E8, 0xCB61B38C,
    0x9B64C2B0, 0x86D3D2D4, 0xA00AE278, 0xBDBDF21C,
};

uint32_t evo_png_crc32(uint32_t crc, const void *data, size_t len)
{
	const uint8_t *p = data;
	crc = ~crc;
	while (len--) {
		crc ^= *p++;
		crc = (crc >> 4) ^ crc_nibble[crc & 15];
		crc = (crc >> 4) ^ crc_nibble[crc & 15];
	}
	return ~crc;
}

/* ---- writing -------------------------------------------------------- */

static uint8_t *put32(uint8_t *p, uint32_t v)
{
	p[0] = (uint8_t)(v >> 24);
	p[1] = (uint8_t)(v >> 16);
	p[2] = (uint8_t)(v >> 8);
	p[3] = (uint8_t)v;
	return p + 4;
}

static uint32_t get32(const uint8_t *p)
{
	return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 |
	       (uint32_t)p[2] << 8 | p[3];
}

/* Close a chunk whose length and type start at `start` and whose data
 * ends at p: fill in the length, append the CRC of type and data. */
static uint8_t *end_chunk(uint8_t *start, uint8_t *p)
{
	put32(start, (uint32_t)(p - start - 8));
	return put32(p, evo_png_crc32(0, start + 4, (size_t)(p - start - 4)));
}

static int check_shape(int w, int h, int channels, evo_err *err)
{
	if (w < 1 || h < 1 || w > EVO_PNG_MAX_SIDE || h > EVO_PNG_MAX_SIDE)
		return evo_fail(err,
				"PNG of %d x %d pixels: each side must be in "
				"[1, %d]",
				w, h, EVO_PNG_MAX_SIDE);
	if (channels != 3 && channels != 4)
		return evo_fail(err,
				"PNG with %d channels: evo writes 3 (RGB) or "
				"4 (RGBA)",
				channels);
	return 0;
}

/* compress2's zlib stream of raw into z (*zlen bytes there, then the
 * stream's length), with run-length matches only (Z_RLE): evo's pictures
 * are mostly runs of one colour, which it finds in a third of the time
 * the default search takes (the learning curve drawn during a run of XOR
 * cost more than its generations). Z_OK, or zlib's error. */
static int deflate_rle(uint8_t *z, uLongf *zlen, const uint8_t *raw,
		       uLong rawlen)
{
	z_stream st;
	memset(&st, 0, sizeof st);
	int rc =
	    deflateInit2(&st, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15, 8, Z_RLE);
	if (rc != Z_OK)
		return rc;
	st.next_in = (Bytef *)(uintptr_t)raw;
	st.avail_in = (uInt)rawlen;
	st.next_out = z;
	st.avail_out = (uInt)*zlen;
	rc = deflate(&st, Z_FINISH);
	*zlen = st.total_out;
	deflateEnd(&st);
	return rc == Z_STREAM_END ? Z_OK : rc == Z_OK ? Z_BUF_ERROR : rc;
}

/* The file around rows already laid out with their filter bytes (raw,
 * rawlen bytes): IHDR with `depth` bits per sample and colour type
 * `ctype`, PLTE of `ncolours` entries when there is a palette, IDAT,
 * IEND. */
static int encode_rows(const uint8_t *raw, size_t rawlen, int w, int h,
		       int depth, int ctype, const uint8_t *plte, int ncolours,
		       uint8_t **png, size_t *len, evo_err *err)
{
	uLong zcap = compressBound((uLong)rawlen);
	size_t total =
	    sizeof signature + (12 + 13) + (12 + 3 * 256) + (12 + zcap) + 12;
	uint8_t *out = malloc(total);
	if (!out)
		return evo_fail(err, "PNG of %d x %d pixels: out of memory", w,
				h);
	uint8_t *p = out, *chunk;
	memcpy(p, signature, sizeof signature);
	p += sizeof signature;

	chunk = p;
	p = put32(p, 0);
	memcpy(p, "IHDR", 4);
	p = put32(put32(p + 4, (uint32_t)w), (uint32_t)h);
	*p++ = (uint8_t)depth; /* bits per sample */
	*p++ = (uint8_t)ctype; /* colour type */
	*p++ = 0;	       /* compression: deflate */
	*p++ = 0;	       /* filter method 0 */
	*p++ = 0;	       /* no interlace */
	p = end_chunk(chunk, p);

	if (ncolours > 0) {
		chunk = p;
		p = put32(p, 0);
		memcpy(p, "PLTE", 4);
		memcpy(p + 4, plte, (size_t)ncolours * 3);
		p = end_chunk(chunk, p + 4 + (size_t)ncolours * 3);
	}

	chunk = p;
	p = put32(p, 0);
	memcpy(p, "IDAT", 4);
	p += 4;
	uLongf zlen = zcap;
	int zrc = deflate_rle(p, &zlen, raw, (uLong)rawlen);
	if (zrc != Z_OK) {
		free(out);
		return evo_fail(err, "PNG of %d x %d pixels: zlib: %s", w, h,
				zError(zrc));
	}
	p = end_chunk(chunk, p + zlen);

	chunk = p;
	p = put32(p, 0);
	memcpy(p, "IEND", 4);
	p = end_chunk(chunk, p + 4);

	*png = out;
	*len = (size_t)(p - out);
	return 0;
}

int evo_png_encode(const uint8_t *pixels, int w, int h, int channels,
		   uint8_t **png, size_t *len, evo_err *err)
{
	*png = NULL;
	*len = 0;
	if (check_shape(w, h, channels, err))
		return -1;
	/* Sides of at most 2^14 keep every size below 2^32. */
	size_t row = (size_t)w * channels, rawlen = (size_t)h * (row + 1);
	uint8_t *raw = malloc(rawlen);
	if (!raw)
		return evo_fail(err, "PNG of %d x %d pixels: out of memory", w,
				h);
	for (int y = 0; y < h; y++) {
		uint8_t *r = raw + (size_t)y * (row + 1);
		r[0] = 0; /* filter None */
		memcpy(r + 1, pixels + (size_t)y * row, row);
	}
	int rc = encode_rows(raw, rawlen, w, h, 8, channels == 4 ? 6 : 2, NULL,
			     0, png, len, err);
	free(raw);
	return rc;
}

/* ---- palette images ------------------------------------------------- */

/* Colours seen so far, 0xRRGGBB + 1 (0: free slot) in an open-addressed
 * table of 1024 slots (at most 257 used), beside their palette index. */
typedef struct palette {
	uint32_t key[1024];
	uint8_t index[1024];
	uint8_t rgb[3 * 256];
	int n;
} palette;

/* The palette index of colour rgb, added if new; -1 past 256 colours. */
static int palette_index(palette *pal, uint32_t rgb)
{
	uint32_t key = rgb + 1, at = (key * 2654435761u) >> 22;
	while (pal->key[at] && pal->key[at] != key)
		at = (at + 1) & 1023;
	if (pal->key[at])
		return pal->index[at];
	if (pal->n == 256)
		return -1;
	pal->key[at] = key;
	pal->index[at] = (uint8_t)pal->n;
	pal->rgb[3 * pal->n] = (uint8_t)(rgb >> 16);
	pal->rgb[3 * pal->n + 1] = (uint8_t)(rgb >> 8);
	pal->rgb[3 * pal->n + 2] = (uint8_t)rgb;
	return pal->n++;
}

static uint64_t load64(const uint8_t *p)
{
	uint64_t v;
	memcpy(&v, p, sizeof v);
	return v;
}

/* Each RGB pixel's palette index into idx (one byte each), the palette
 * in *pal; -1 when the image has more than 256 colours. A run of one
 * colour is found 8 bytes at a time: pixels i+1.. repeat pixel i as long
 * as each byte equals the one 3 before it. */
static int index_pixels(const uint8_t *px, size_t n, palette *pal, uint8_t *idx)
{
	memset(pal, 0, sizeof *pal);
	size_t end = 3 * n;
	for (size_t i = 0; i < n;) {
		const uint8_t *p = px + 3 * i;
		int k = palette_index(pal, (uint32_t)p[0] << 16 |
					       (uint32_t)p[1] << 8 | p[2]);
		if (k < 0)
			return -1;
		size_t b = 3 * i + 3;
		while (b + 8 <= end && load64(px + b) == load64(px + b - 3))
			b += 8;
		while (b < end && px[b] == px[b - 3])
			b++;
		size_t next = b / 3; /* the first pixel with another byte */
		memset(idx + i, k, next - i);
		i = next;
	}
	return 0;
}

/* A row of w indices packed `depth` bits each (1 or 2) into r, the
 * leftmost in the high bits of its byte, the last byte's unused low
 * bits 0. */
static void pack_row(uint8_t *r, const uint8_t *in, int w, int depth)
{
	unsigned acc = 0;
	int bits = 0;
	for (int x = 0; x < w; x++) {
		acc = acc << depth | in[x];
		bits += depth;
		if (bits == 8) {
			*r++ = (uint8_t)acc;
			acc = 0;
			bits = 0;
		}
	}
	if (bits)
		*r = (uint8_t)(acc << (8 - bits));
}

/* The same for 4 bits: two pixels a byte. */
static void pack_row4(uint8_t *r, const uint8_t *in, int w)
{
	int x = 0;
	for (; x + 1 < w; x += 2)
		*r++ = (uint8_t)(in[x] << 4 | in[x + 1]);
	if (x < w)
		*r = (uint8_t)(in[x] << 4);
}

/* The fewest bits a palette index of n colours needs that PNG allows. */
static int depth_for(int n)
{
	return n <= 2 ? 1 : n <= 4 ? 2 : n <= 16 ? 4 : 8;
}

int evo_png_encode_indexed(const uint8_t *pixels, int w, int h, uint8_t **png,
			   size_t *len, evo_err *err)
{
	*png = NULL;
	*len = 0;
	if (check_shape(w, h, 3, err))
		return -1;
	size_t n = (size_t)w * (size_t)h;
	palette *pal = malloc(sizeof *pal);
	uint8_t *idx = malloc(n);
	if (!pal || !idx) {
		free(pal);
		free(idx);
		return evo_fail(err, "PNG of %d x %d pixels: out of memory", w,
				h);
	}
	if (index_pixels(pixels, n, pal, idx)) {
		free(pal);
		free(idx);
		return evo_png_encode(pixels, w, h, 3, png, len, err);
	}
	int depth = depth_for(pal->n);
	size_t row = ((size_t)w * depth + 7) / 8,
	       rawlen = (size_t)h * (row + 1);
	uint8_t *raw = malloc(rawlen);
	int rc = -1;
	if (!raw) {
		evo_fail(err, "PNG of %d x %d pixels: out of memory", w, h);
		goto out;
	}
	/* Each row: its filter byte 0 (None), then the indices. */
	for (int y = 0; y < h; y++) {
		uint8_t *r = raw + (size_t)y * (row + 1);
		const uint8_t *in = idx + (size_t)y * w;
		*r++ = 0;
		if (depth == 8)
			memcpy(r, in, (size_t)w);
		else if (depth == 4)
			pack_row4(r, in, w);
		else
			pack_row(r, in, w, depth);
	}
	rc = encode_rows(raw, rawlen, w, h, depth, 3, pal->rgb, pal->n, png,
			 len, err);
out:
	free(raw);
	free(pal);
	free(idx);
	return rc;
}

/* An encoded PNG (encoded: its encoder's result) written to path by
 * put and freed; an encoder's failure said with the path. */
typedef int (*write_fn)(const char *path, const void *data, size_t len,
			evo_err *err);
static int write_encoded(const char *path, int encoded, uint8_t *png,
			 size_t len, write_fn put, evo_err *err)
{
	if (encoded) {
		char why[sizeof err->msg];
		snprintf(why, sizeof why, "%s", err ? err->msg : "");
		return evo_fail(err, "%s: %s", path, why);
	}
	int rc = put(path, png, len, err);
	free(png);
	return rc;
}

int evo_png_write(const char *path, const uint8_t *pixels, int w, int h,
		  int channels, evo_err *err)
{
	uint8_t *png = NULL;
	size_t len = 0;
	int rc = evo_png_encode(pixels, w, h, channels, &png, &len, err);
	return write_encoded(path, rc, png, len, evo_write_file_atomic, err);
}

int evo_png_write_indexed(const char *path, const uint8_t *pixels, int w, int h,
			  evo_err *err)
{
	uint8_t *png = NULL;
	size_t len = 0;
	int rc = evo_png_encode_indexed(pixels, w, h, &png, &len, err);
	return write_encoded(path, rc, png, len, evo_write_file_replace, err);
}

/* ---- reading -------------------------------------------------------- */

void evo_png_image_free(evo_png_image *img)
{
	free(img->pixels);
	memset(img, 0, sizeof *img);
}

/* The zlib stream, gathered from the IDAT chunks, inflated into exactly
 * the filtered rows the header implies: no more, no less, and nothing
 * after the stream's end. zlib checks the stream's Adler-32. */
static int inflate_rows(const uint8_t *z, size_t zlen, uint8_t *raw,
			size_t rawlen, evo_err *err)
{
	z_stream s;
	memset(&s, 0, sizeof s);
	if (inflateInit(&s) != Z_OK)
		return evo_fail(err, "zlib: cannot start inflating");
	s.next_in = (Bytef *)z;
	s.avail_in = (uInt)zlen;
	s.next_out = raw;
	s.avail_out = (uInt)rawlen;
	int zrc = inflate(&s, Z_FINISH);
	size_t out = s.total_out, left = s.avail_in, room = s.avail_out;
	char why[64];
	snprintf(why, sizeof why, "%s", s.msg ? s.msg : zError(zrc));
	inflateEnd(&s);
	if (zrc == Z_STREAM_END) {
		if (out != rawlen)
			return evo_fail(err,
					"image data has %zu bytes, its header "
					"implies %zu",
					out, rawlen);
		if (left)
			return evo_fail(
			    err, "zlib stream: %zu bytes after its end", left);
		return 0;
	}
	/* Stuck with input left: no room for more rows; with none left:
	 * the stream stops before its end. */
	if (zrc == Z_BUF_ERROR && left > 0 && room == 0)
		return evo_fail(err,
				"image data is longer than the %zu bytes its "
				"header implies",
				rawlen);
	if (zrc == Z_BUF_ERROR && left == 0)
		return evo_fail(err,
				"image data is cut off: the zlib stream stops "
				"before its end, after %zu of %zu bytes",
				out, rawlen);
	return evo_fail(err, "image data is damaged: zlib: %s", why);
}

/* A palette image's row of w indices, `depth` bits each (leftmost in the
 * high bits), as RGB pixels into `to`; -1 on an index past the palette. */
static int unpack_row(const uint8_t *r, int w, int depth, const uint8_t *plte,
		      int ncolours, uint8_t *to)
{
	int per = 8 / depth, mask = (1 << depth) - 1;
	for (int x = 0; x < w; x += per, r++)
		for (int k = 0; k < per && x + k < w; k++, to += 3) {
			int i = *r >> (8 - depth * (k + 1)) & mask;
			if (i >= ncolours)
				return -1;
			memcpy(to, plte + 3 * i, 3);
		}
	return 0;
}

static int decode(const uint8_t *png, size_t len, evo_png_image *img,
		  evo_err *err)
{
	if (len < sizeof signature || memcmp(png, signature, sizeof signature))
		return evo_fail(err, "not a PNG file (no PNG signature)");
	size_t at = sizeof signature;
	int w = 0, h = 0, channels = 0, seen_idat = 0, idat_done = 0;
	int depth = 8, ctype = 2, ncolours = 0;
	uint8_t plte[3 * 256];
	uint8_t *z = NULL;
	size_t zlen = 0;
	int rc = -1;
	for (int index = 0;; index++) {
		if (len - at < 12) {
			evo_fail(err,
				 "file ends inside chunk %d at byte %zu "
				 "(no IEND)",
				 index, at);
			goto out;
		}
		uint32_t n = get32(png + at);
		const uint8_t *type = png + at + 4, *data = png + at + 8;
		char name[5];
		for (int k = 0; k < 4; k++)
			name[k] = (type[k] >= 'A' && type[k] <= 'Z') ||
					  (type[k] >= 'a' && type[k] <= 'z')
				      ? (char)type[k]
				      : '?';
		name[4] = 0;
		if (n > len - at - 12) {
			evo_fail(err,
				 "chunk %d (%s) at byte %zu: %u bytes of data "
				 "announced, %zu left",
				 index, name, at, n, len - at - 12);
			goto out;
		}
		uint32_t want = get32(data + n),
			 got = evo_png_crc32(0, type, n + 4u);
		if (want != got) {
			evo_fail(err,
				 "chunk %d (%s) at byte %zu is damaged: "
				 "CRC-32 0x%08X, the file says 0x%08X",
				 index, name, at, got, want);
			goto out;
		}
		at += 12 + (size_t)n;
		if (index == 0 && memcmp(type, "IHDR", 4)) {
			evo_fail(err, "first chunk is %s, want IHDR", name);
			goto out;
		}
		if (!memcmp(type, "IHDR", 4)) {
			if (index != 0) {
				evo_fail(err, "a second IHDR (chunk %d)",
					 index);
				goto out;
			}
			if (n != 13) {
				evo_fail(err, "IHDR of %u bytes, want 13", n);
				goto out;
			}
			uint32_t uw = get32(data), uh = get32(data + 4);
			if (uw < 1 || uh < 1 || uw > EVO_PNG_MAX_SIDE ||
			    uh > EVO_PNG_MAX_SIDE) {
				evo_fail(err,
					 "image of %u x %u pixels: each side "
					 "must be in [1, %d]",
					 uw, uh, EVO_PNG_MAX_SIDE);
				goto out;
			}
			w = (int)uw;
			h = (int)uh;
			depth = data[8];
			ctype = data[9];
			if (ctype != 2 && ctype != 3 && ctype != 6) {
				evo_fail(err,
					 "colour type %d: evo reads 2 (RGB), "
					 "3 (palette) and 6 (RGBA)",
					 ctype);
				goto out;
			}
			if (ctype == 3 ? depth != 1 && depth != 2 &&
					     depth != 4 && depth != 8
				       : depth != 8) {
				evo_fail(err,
					 "%d bits per sample: evo reads 8, or "
					 "1, 2, 4 or 8 in a palette image",
					 depth);
				goto out;
			}
			channels = ctype == 6 ? 4 : 3;
			if (data[10] != 0 || data[11] != 0) {
				evo_fail(err,
					 "compression method %d, filter "
					 "method %d: PNG defines only 0",
					 data[10], data[11]);
				goto out;
			}
			if (data[12] != 0) {
				evo_fail(err,
					 "interlace method %d: evo reads only "
					 "0 (none)",
					 data[12]);
				goto out;
			}
			continue;
		}
		if (!memcmp(type, "PLTE", 4)) {
			if (seen_idat || ncolours) {
				evo_fail(err,
					 "PLTE (chunk %d) after the image data "
					 "or a second one",
					 index);
				goto out;
			}
			if (n == 0 || n % 3 || n / 3 > 256 ||
			    (ctype == 3 && n / 3 > (1u << depth))) {
				evo_fail(err,
					 "PLTE of %u bytes: want 3 a colour, "
					 "1 to %d colours",
					 n,
					 ctype == 3 && depth < 8 ? 1 << depth
								 : 256);
				goto out;
			}
			/* An RGB image's PLTE only suggests colours. */
			ncolours = (int)(n / 3);
			memcpy(plte, data, n);
			continue;
		}
		if (!memcmp(type, "IDAT", 4)) {
			if (ctype == 3 && !ncolours) {
				evo_fail(err,
					 "palette image without a PLTE chunk "
					 "before its data");
				goto out;
			}
			/* PNG requires the IDAT chunks to be consecutive. */
			if (idat_done) {
				evo_fail(err,
					 "IDAT chunk %d after another chunk "
					 "ended the image data",
					 index);
				goto out;
			}
			seen_idat = 1;
			/* The stream cannot be longer than the file: one
			 * buffer of that size holds every IDAT. */
			if (!z && !(z = malloc(len))) {
				evo_fail(err, "out of memory");
				goto out;
			}
			memcpy(z + zlen, data, n);
			zlen += n;
			continue;
		}
		if (seen_idat)
			idat_done = 1;
		if (!memcmp(type, "IEND", 4)) {
			if (at != len) {
				evo_fail(err, "%zu bytes after IEND, want none",
					 len - at);
				goto out;
			}
			break;
		}
		/* Bit 5 of the first letter (lower case) marks a chunk a
		 * reader may skip; any other one changes the meaning of the
		 * image (PLTE, a new critical chunk). */
		if (!(type[0] & 0x20)) {
			evo_fail(err,
				 "critical chunk %s (chunk %d): evo reads "
				 "only IHDR, PLTE, IDAT and IEND",
				 name, index);
			goto out;
		}
	}
	if (!seen_idat) {
		evo_fail(err, "no IDAT chunk: the file holds no image data");
		goto out;
	}
	size_t row = ((size_t)w * (ctype == 3 ? 1 : channels) * depth + 7) / 8,
	       rawlen = (size_t)h * (row + 1);
	/* Deflate writes at most 258 bytes for a length code and a distance
	 * code of at least 1 bit each, so it packs at most 1032 bytes into
	 * one: a header whose sizes the stream cannot fill is refused before
	 * we allocate what it announces. */
	if (rawlen / 1032 > zlen) {
		evo_fail(err,
			 "image data has %zu bytes, fewer than deflate needs "
			 "for the %zu bytes of rows of a %d x %d image",
			 zlen, rawlen, w, h);
		goto out;
	}
	uint8_t *raw = malloc(rawlen);
	img->pixels = malloc((size_t)w * channels * (size_t)h);
	if (!raw || !img->pixels) {
		free(raw);
		evo_fail(err, "image of %d x %d pixels: out of memory", w, h);
		goto out;
	}
	if (inflate_rows(z, zlen, raw, rawlen, err)) {
		free(raw);
		goto out;
	}
	for (int y = 0; y < h; y++) {
		const uint8_t *r = raw + (size_t)y * (row + 1);
		if (r[0] != 0) {
			evo_fail(err,
				 "row %d uses filter type %d: evo reads only "
				 "0 (None), as it writes",
				 y, r[0]);
			free(raw);
			goto out;
		}
		uint8_t *to = img->pixels + (size_t)y * w * channels;
		if (ctype != 3)
			memcpy(to, r + 1, row);
		else if (unpack_row(r + 1, w, depth, plte, ncolours, to)) {
			evo_fail(err,
				 "row %d has a palette index past the "
				 "palette's %d colours",
				 y, ncolours);
			free(raw);
			goto out;
		}
	}
	free(raw);
	img->w = w;
	img->h = h;
	img->channels = channels;
	rc = 0;
out:
	free(z);
	if (rc)
		evo_png_image_free(img);
	return rc;
}

int evo_png_decode(const uint8_t *png, size_t len, evo_png_image *img,
		   evo_err *err)
{
	memset(img, 0, sizeof *img);
	return decode(png, len, img, err);
}

int evo_png_read(const char *path, evo_png_image *img, evo_err *err)
{
	memset(img, 0, sizeof *img);
	char *data;
	size_t len;
	if (evo_read_file(path, &data, &len, err))
		return -1;
	evo_err why;
	int rc = decode((const uint8_t *)data, len, img, &why);
	free(data);
	if (rc)
		return evo_fail(err, "%s: %s", path, why.msg);
	return 0;
}
