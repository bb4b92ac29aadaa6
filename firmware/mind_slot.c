/* The mind slot (mind_slot.h): the exported image, placed by the linker
 * script at the start of the MIND region, which it pads to its full size
 * so that another image can replace it in place. */
#include "mind_slot.h"

#define EVO_MIND_IMAGE_ATTR __attribute__((section(".mind")))
#include "mind.h" /* from evo export --format c */

extern const uint8_t __mind_end[];

const uint8_t *const fw_mind_slot = evo_mind_image;

size_t fw_mind_slot_size(void)
{
	return (size_t)((uintptr_t)__mind_end - (uintptr_t)evo_mind_image);
}
