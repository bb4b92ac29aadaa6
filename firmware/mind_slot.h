/* The mind slot: the region of flash that holds the mind image, linked
 * from the header `evo export --format c` writes, or written on its own
 * (docs/firmware.md: reflashing a mind). */
#ifndef EVO_FW_MIND_SLOT_H
#define EVO_FW_MIND_SLOT_H

#include <stddef.h>
#include <stdint.h>

/* The slot's first byte (4-byte aligned) and its size in bytes; the image
 * at its start says its own length. */
extern const uint8_t *const fw_mind_slot;
size_t fw_mind_slot_size(void);

#endif
