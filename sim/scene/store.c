/* The storage of a scene of either dimension (sim/scene/store.h). */
#include "scene/store.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int evo_store_grow(void **items, int *cap, int need, size_t size, evo_err *err)
{
	if (need <= *cap)
		return 0;
	int n = *cap ? *cap * 2 : 8;
	while (n < need)
		n *= 2;
	void *p = realloc(*items, (size_t)n * size);
	if (!p)
		return evo_fail(err, "out of memory");
	memset((char *)p + (size_t)*cap * size, 0, (size_t)(n - *cap) * size);
	*items = p;
	*cap = n;
	return 0;
}

int evo_store_name(char *out, const char *name, const char *dflt, int index,
		   evo_err *err)
{
	out[0] = 0;
	if (name && strlen(name) >= EVO_PIECE_NAME_MAX)
		return evo_fail(err, "name '%.40s...' is longer than %d bytes",
				name, EVO_PIECE_NAME_MAX - 1);
	if (name && name[0])
		snprintf(out, EVO_PIECE_NAME_MAX, "%s", name);
	else if (dflt)
		snprintf(out, EVO_PIECE_NAME_MAX, "%s%d", dflt, index + 1);
	return 0;
}

int evo_store_find(const void *items, int n, size_t stride, size_t name_at,
		   const char *name)
{
	const char *p = items;
	for (int i = 0; i < n; i++, p += stride)
		if (strcmp(p + name_at, name) == 0)
			return i;
	return -1;
}

void *evo_store_add(void **items, int *cap, int n, size_t size, evo_err *err)
{
	if (cap && evo_store_grow(items, cap, n + 1, size, err))
		return NULL;
	if (!cap && n % 8 == 0) {
		void *p = realloc(*items, (size_t)(n + 8) * size);
		if (!p) {
			evo_fail(err, "out of memory");
			return NULL;
		}
		*items = p;
	}
	return memset((char *)*items + (size_t)n * size, 0, size);
}
