/* The mind slots (mind_slot.h). Slot 0 is the exported image, placed by
 * the linker script at the start of the MIND region, which it pads to its
 * full size so that another image can replace it in place; slot 1 is the
 * MIND_B region, which nothing is linked into. */
#include "mind_slot.h"

#include "board.h"
#include "evo/flash.h"

#define EVO_MIND_IMAGE_ATTR __attribute__((section(".mind")))
#include "mind.h" /* from evo export --format c */

extern const uint8_t __mind_end[], __mind_b[];

const uint8_t *const fw_slot[FW_SLOTS] = {evo_mind_image, __mind_b};

size_t fw_slot_size(void)
{
	return (size_t)((uintptr_t)__mind_end - (uintptr_t)evo_mind_image);
}

int fw_slot_write(void *rx, uint32_t offset, const uint8_t word[4])
{
	uint32_t addr =
	    (uint32_t)(uintptr_t)((evo_flash_rx *)rx)->slot + offset;
	if (offset % BOARD_FLASH_PAGE == 0)
		board_flash_erase(addr);
	board_flash_write(addr, evo_wire_get_u32(word));
	return 0; /* the receiver reads the word back for its CRC */
}

void fw_slot_retire(unsigned i)
{
	board_flash_write((uint32_t)(uintptr_t)fw_slot[i], 0);
}
