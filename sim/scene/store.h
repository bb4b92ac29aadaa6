/* evo — the storage of a scene of either dimension (docs/architecture.md,
 * "Where the layout is going", step 3): its arrays that grow as pieces are
 * added, the names of its pieces, and lookups by name. The 2D scene
 * (world2d/scene.c) and the 3D one (world3d/scene3d.c) keep their elements,
 * bots, sensors, actuators, rewards and controls with these. */
#ifndef EVO_STORE_H
#define EVO_STORE_H

#include <stddef.h>

#include "base/err.h"

/* The longest name of a piece, with its NUL. */
#define EVO_PIECE_NAME_MAX 64

/* Room for `need` items of `size` bytes in *items (capacity *cap, doubled
 * from 8 as needed; new room zeroed): 0, or -1 with err set. */
int evo_store_grow(void **items, int *cap, int need, size_t size, evo_err *err);

/* A piece's name into out (EVO_PIECE_NAME_MAX bytes): name, or when name is
 * NULL or "", dflt followed by index + 1 ("bot2"), or "" when dflt is NULL
 * too. 0, or -1 with err set for a name too long. */
int evo_store_name(char *out, const char *name, const char *dflt, int index,
		   evo_err *err);

/* The index of the item among n items of `stride` bytes whose name (a char
 * array name_at bytes into each) is name; -1 when none. */
int evo_store_find(const void *items, int n, size_t stride, size_t name_at,
		   const char *name);
/* The same over owner's array `arr` of n_<arr>s items of `type`, whose
 * name is its member `name` (a scene's bots, a bot's sensors). */
#define EVO_FIND(owner, arr, type, key)                                        \
	evo_store_find((owner)->arr, (owner)->n_##arr##s, sizeof(type),        \
		       offsetof(type, name), key)

/* Room for item n of an array of n items (capacity *cap, as
 * evo_store_grow; cap NULL: an array that grows 8 at a time, a bot's
 * sensors and actuators): the new item, zeroed, or NULL with err set. */
void *evo_store_add(void **items, int *cap, int n, size_t size, evo_err *err);

#endif
