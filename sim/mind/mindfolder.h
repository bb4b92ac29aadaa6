/* The mind loader: reads a mind folder and builds its mind model.
 *
 * A mind folder <root>/ named after its agent <Bot> holds
 *     <Bot>.botdesc                sensors and actuators
 *     <Bot>.vardesc                variables (optional: none if absent)
 *     Skills/<Name>/<Name>.ades    one per skill
 *     Skills/<Name>/<Name>.net     a neural skill's trained network
 *     Tasks/<Task>.simbatch         tasks
 * Every skill reachable from the master skill through SK outputs is read;
 * skills are put in a fixed top-down order (master first, every skill
 * before its sub-skills) and every name is resolved. docs/mind.md. */
#ifndef EVO_MIND_LOAD_H
#define EVO_MIND_LOAD_H

#include "base/err.h"
#include "evo/evo.h"

/* A network a neural skill runs instead of its Skills/<S>/<S>.net
 * (`evo run --net SKILL=SOURCE`, docs/running.md): SOURCE is a .net file
 * (a run folder's best/gen-NNNN.net or champion.net), "random" (a layered
 * network of random weights, from the seed) or "zero" (a layered network
 * of zero weights: every output 0.5). */
typedef struct evo_net_choice {
	const char *skill;
	const char *source;
} evo_net_choice;

typedef struct evo_mindfolder_opts {
	/* The master skill; NULL: the one skill of Skills/ that no other
	 * skill names in an SK output. */
	const char *master;
	/* A neural skill being trained: it may lack a .net; it then gets a
	 * layered network with zero weights (every output 0.5). */
	const char *learning_skill;
	/* Networks chosen for some neural skills, and the seed of the
	 * "random" ones. Each must name a neural skill of the hierarchy. */
	const evo_net_choice *nets;
	unsigned n_nets;
	uint64_t seed;
	/* evo info and evo check: a neural skill without a .net (not trained
	 * yet) gets the zero-weight placeholder and is marked in untrained[]
	 * instead of failing the load */
	int untrained_ok;
} evo_mindfolder_opts;

typedef struct evo_mindfolder {
	char *root;	/* the mind folder, as given */
	char *bot_name; /* its last path component */
	evo_botdesc *botdesc;
	evo_vardesc *vardesc;
	unsigned n_skills; /* top-down order, master first */
	evo_ades *skill;
	evo_netdesc **net; /* per skill; NULL for hard-coded */
	unsigned char *untrained; /* per skill: 1 for a neural skill with no
				   * .net yet (only with untrained_ok), 2
				   * for the learning skill with none: the
				   * task trains it, nothing else must */
	uint32_t names_hash;
	void *image; /* the mind image (the model) */
	size_t image_len;
	evo_mind mind; /* a view over image */
} evo_mindfolder;

/* Load the mind folder at root. Returns NULL with err set to
 * "file:line: what was wrong" on any problem. */
evo_mindfolder *evo_mindfolder_load(const char *root,
				    const evo_mindfolder_opts *opts,
				    evo_err *err);

void evo_mindfolder_free(evo_mindfolder *l);

/* Skill index in l's order, or -1. */
int evo_mindfolder_skill(const evo_mindfolder *l, const char *name);

/* Rebuild l's image after changing l->net[...] (e.g. a new candidate
 * network for the learning skill). */
int evo_mindfolder_rebuild(evo_mindfolder *l, evo_err *err);

/* The names hash of a botdesc and vardesc (vardesc may be NULL). */
uint32_t evo_names_hash_of(const evo_botdesc *b, const evo_vardesc *v);

#endif
