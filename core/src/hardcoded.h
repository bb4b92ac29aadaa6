/* Private: the hard-coded classes as the tick sees them (hardcoded.c). */
#ifndef EVO_HARDCODED_H
#define EVO_HARDCODED_H

#include "evo/mind.h"

/* A row of evo_hc_classes without its name: hash is evo_name_hash(name). */
typedef struct hc_class {
	uint32_t hash;
	int8_t n_in, n_out; /* required counts, -1 for any */
	evo_hc_fn fn;
} hc_class;

/* In the order of evo_hc_classes: index i is the same class in both. */
extern const hc_class hc_table[];

/* The index of the class whose name hashes to hash, or -1. */
int hc_index_of(uint32_t hash);

#endif
