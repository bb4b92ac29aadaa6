/* The mind slots: two regions of flash of the same size, each able to
 * hold a mind image. Slot 0 (at 0xE000) holds the image the firmware was
 * built with, linked from the header `evo export --format c` writes, or
 * written on its own (docs/firmware.md: reflashing a mind); slot 1 (at
 * 0xC000) is where `evo flash` writes a mind while the other one runs,
 * and then the two swap roles (docs/firmware.md, "Sending a mind"). */
#ifndef EVO_FW_MIND_SLOT_H
#define EVO_FW_MIND_SLOT_H

#include <stddef.h>
#include <stdint.h>

#define FW_SLOTS 2

/* Each slot's first byte (4-byte aligned, page-aligned); the image at its
 * start says its own length. */
extern const uint8_t *const fw_slot[FW_SLOTS];

/* The bytes of each slot. */
size_t fw_slot_size(void);

/* evo_flash_write_fn for the receiver rx (an evo_flash_rx *): program a
 * word at offset of its target slot, erasing each page as the transfer
 * enters it. */
int fw_slot_write(void *rx, uint32_t offset, const uint8_t word[4]);

/* Slot i no longer boots: its magic word is cleared (one word written,
 * which NOR flash does without an erase). */
void fw_slot_retire(unsigned i);

#endif
