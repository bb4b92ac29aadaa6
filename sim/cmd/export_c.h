/* `evo export --format c`: a mind image as a C header of const data, for a
 * firmware that carries its mind in flash (docs/firmware.md). */
#ifndef EVO_EXPORT_C_H
#define EVO_EXPORT_C_H

#include <stddef.h>

#include "base/err.h"
#include "mind/mindfolder.h"

/* The C header for l's image: a malloc'd NUL-terminated text (*len
 * excludes the NUL), or NULL with err set. The header defines
 *     EVO_MIND_IMAGE_NAME        the mind's name, a string
 *     EVO_MIND_IMAGE_LEN         bytes of the image
 *     EVO_MIND_IMAGE_NAMES_HASH  the names hash the image was built for
 *     evo_mind_image[]           the image, static const, 4-byte aligned
 * and puts EVO_MIND_IMAGE_ATTR (empty unless the includer defines it, e.g.
 * as a section attribute) before the array. */
char *evo_export_c(const evo_mindfolder *l, size_t *len, evo_err *err);

#endif
