/* evo — the elements of a scene of either dimension (docs/architecture.md,
 * "Where the layout is going", step 4): one definition, `evo_element_def`,
 * and one element, `evo_element`, for the 2D scene (world2d/scene.h) and
 * the 3D one (world3d/scene3d.h), their defaults, and the part of adding
 * one that both worlds share: the checks, the name and the stored copy.
 * What is only the world's (a Box2D obstacle or body, an ODE shape) stays
 * in world2d/scene.c and world3d/scene3d.c.
 *
 * The kind is scene/kinds.h's evo_piece_kind (EVO_PIECE_CYLINDER ..
 * EVO_PIECE_TARGET); which kinds each world has is its row of kinds.c
 * (2D: cylinder, box, zone, object; 3D all six). Each field says which
 * world reads it. Where both worlds keep one quantity under two names an
 * anonymous union gives both spellings: x, y, z are pos[0..2] (2D leaves z
 * 0); a box's half_w, half_h, half_d are half[0..2]; a 2D size is a 3D
 * radius; 2D's angle is 3D's yaw (a turn about the frame's third axis, in
 * the frame's own sense). */
#ifndef EVO_ELEMENT_H
#define EVO_ELEMENT_H

#include "base/err.h"
#include "scene/backend.h"
#include "scene/kinds.h"
#include "scene/place.h"
#include "scene/store.h"

typedef struct evo_element_def {
	evo_piece_kind kind; /* both: EVO_PIECE_CYLINDER .. EVO_PIECE_TARGET */
	const char *name;    /* both; may be NULL */
	/* both: its centre (2D: x, y; 3D: pos[]) */
	EVO_POSITION;
	/* both: its turn (2D: angle, clockwise on screen; 3D: yaw) */
	EVO_TURN;
	/* both: 2D a cylinder's and an object's radius, a zone's half side;
	 * 3D a cylinder's, sphere's, target's and sphere object's radius */
	union {
		double size;
		double radius;
	};
	/* both: a box's half sides (2D half_w, half_h; 3D half[] of a box, a
	 * zone and a box object) */
	union {
		double half[3];
		struct {
			double half_w, half_h, half_d;
		};
	};
	double half_length; /* 3D: a cylinder's half height */
	double mass;	    /* 3D: an object's (1 kg) */
	double friction;    /* both: 2D an object's (0), 3D (0.5) */
	/* 2D: an object's Box2D properties (density 2, restitution 0,
	 * linear and angular damping 5) */
	double density, restitution, linear_damping, angular_damping;
	int sphere; /* 3D: an object is a sphere (1) or a box (0) */
	/* 3D: a box, cylinder or sphere is part of the ground (a bump, a
	 * ramp): touching it is no collision, and rays see it only where
	 * they see the ground */
	int ground;
} evo_element_def;

/* The defaults of kind in world dim (EVO_DIM_2D or EVO_DIM_3D): 2D's are
 * EvoAgents' (size and half sides 1), 3D's half a metre; one function for
 * both, since the worlds' scales differ. */
evo_element_def evo_default_element_def(evo_piece_kind kind, unsigned dim);

typedef struct evo_element {
	evo_piece_kind kind; /* both: def.kind */
	char name[EVO_PIECE_NAME_MAX];
	evo_element_def def; /* both: as added (def.name NULL: name is it) */
	/* both: where it is. 2D: where it starts each episode (an object's
	 * current place after each step); 3D: now (objects move; a reset
	 * puts it back at def.pos) */
	EVO_POSITION;
	double angle; /* 2D: its turn now (def.angle, an object's moves) */
	double size;  /* 2D: def.size */
	union {	      /* 2D: def.half_w, def.half_h */
		double half[3];
		struct {
			double half_w, half_h, half_d;
		};
	};
	double R[9]; /* 3D: an object's turn */
	/* both: 1 unless switched off. An inactive zone or target is seen by
	 * no sensor and pays no reward; an inactive object is off the world
	 * (2D: delivered, gathered or set off; 3D: set off) until the next
	 * reset. */
	int active;
	int held_by;	  /* 2D: objects: the bot whose claw holds it, or -1 */
	evo_body_id body; /* both: an object's body, else EVO_BODY_NONE */
	int obstacle;	  /* both: a static solid's obstacle index, else -1 */
} evo_element;

/* Whether kind is a static solid (a cylinder, box or sphere): an obstacle
 * of the world, by its kind and never by its number. */
static inline int evo_element_is_solid(evo_piece_kind kind)
{
	return kind == EVO_PIECE_CYLINDER || kind == EVO_PIECE_BOX ||
	       kind == EVO_PIECE_SPHERE;
}

/* Adding an element, both worlds' part: checks d for world dim (a kind of
 * that world, numbers, positive sizes, a name not used in the first n
 * elements of *arr) and stores it as element n of *arr (capacity *cap),
 * named d->name or, unnamed, dflt and its number ("element3"; "" when
 * dflt is NULL), active, held by no one, with no body or obstacle. The
 * new element, or NULL with err set; the caller counts it once it has
 * made what its world needs. */
evo_element *evo_element_store(evo_element **arr, int *cap, int n,
			       const evo_element_def *d, unsigned dim,
			       const char *dflt, evo_err *err);

#endif
