/* Private: the hard-coded classes as the tick sees them (hardcoded.c). */
#ifndef EVO_HARDCODED_H
#define EVO_HARDCODED_H

#include "evo/mind.h"

/* A row of evo_hc_classes without its name: hash is evo_name_hash(name). */
typedef struct evo_hc_row {
	uint32_t hash;
	int8_t n_in, n_out; /* required counts, -1 for any */
	evo_hc_fn fn;
} evo_hc_row;

/* In the order of evo_hc_classes: index i is the same class in both. */
extern const evo_hc_row evo_hc_table[];

/* The index of the class whose name hashes to hash, or -1. */
int evo_hc_index_of(uint32_t hash);

#endif
