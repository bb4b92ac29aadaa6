/* evo — PNG files through zlib: evo writes 8-bit RGB or RGBA images
 * (screenshots), and palette images of 1 to 8 bits a pixel for drawings
 * of a few colours (learning curves), that every PNG reader opens.
 *
 * The reader takes what the writer makes, so tests can check saved
 * images: 8-bit RGB or RGBA, or a palette image (returned as RGB), no
 * interlace, filter 0 (None) on every row.
 * Anything else, a damaged file above all, is refused with a message that
 * says what was found where; it never crashes and never returns pixels
 * from a damaged file (every chunk's CRC-32 and the stream's Adler-32 are
 * checked). Ancillary chunks (tEXt, gAMA, ...) are skipped. */
#ifndef EVO_PNG_H
#define EVO_PNG_H

#include <stddef.h>
#include <stdint.h>

#include "base/err.h"

/* Largest side either direction accepts (as EVO_RASTER_MAX_SIDE). */
#define EVO_PNG_MAX_SIDE 16384

/* Encode w x h pixels, `channels` bytes each (3: R, G, B; 4: R, G, B, A),
 * rows top first without padding, into a malloc'd PNG (the caller frees
 * *png). Returns 0, or -1 with err set. */
int evo_png_encode(const uint8_t *pixels, int w, int h, int channels,
		   uint8_t **png, size_t *len, evo_err *err);

/* Encode and write to path atomically (a temporary file, then rename). */
int evo_png_write(const char *path, const uint8_t *pixels, int w, int h,
		  int channels, evo_err *err);

/* RGB pixels as evo_png_encode takes them (3 channels), encoded as a
 * palette image when they have at most 256 colours, with the fewest bits
 * a pixel PNG allows (1, 2, 4 or 8), else as RGB. A learning curve's
 * 6 colours take 4 bits a pixel instead of 24: a sixth of the bytes to
 * deflate. Decoded, the pixels are the same. */
int evo_png_encode_indexed(const uint8_t *pixels, int w, int h, uint8_t **png,
			   size_t *len, evo_err *err);
/* Encode as evo_png_encode_indexed and write as evo_png_write, without
 * its fsync (evo_write_file_replace): for a picture drawn again by any
 * later run, such as the learning curve a run redraws as it goes. */
int evo_png_write_indexed(const char *path, const uint8_t *pixels, int w, int h,
			  evo_err *err);

/* A decoded image: pixels as evo_png_encode takes them, malloc'd. */
typedef struct evo_png_image {
	int w, h, channels;
	uint8_t *pixels;
} evo_png_image;

/* Decode a PNG held in memory. Returns 0, or -1 with err set and *img
 * zeroed. */
int evo_png_decode(const uint8_t *png, size_t len, evo_png_image *img,
		   evo_err *err);
/* Read and decode a file; messages start with the path. */
int evo_png_read(const char *path, evo_png_image *img, evo_err *err);
/* Free the pixels and zero the struct; safe on a zeroed struct. */
void evo_png_image_free(evo_png_image *img);

/* The CRC-32 of PNG's chunks, fed in pieces: start with 0. Table-driven
 * (core's evo_crc32 goes bit by bit: fine for a mind image, slow for a
 * screenshot a frame). */
uint32_t evo_png_crc32(uint32_t crc, const void *data, size_t len);

#endif
