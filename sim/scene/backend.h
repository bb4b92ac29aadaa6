/* evo — the physics backend interface: what the scene asks of a physics
 * engine, one struct of functions (docs/architecture.md, "Where the
 * layout is going", step 2).
 *
 * Two fill it: Box2D (sim/world2d/world_box2d.cpp, evo_backend_box2d) for
 * a 2D scene and ODE (sim/world3d/world_ode.c, evo_backend_ode) for a 3D
 * one. A function that does not apply to a backend is NULL in its struct
 * and says so below ("2D only", "3D only"): the scene of the other dimension
 * never calls it.
 *
 * Frame and units: metres, kilograms, seconds, radians. Positions have
 * three numbers; a 2D backend keeps z = 0 and turns about z only, so its
 * turns are a yaw. Bodies are reached through ids (index + generation):
 * a stale id is refused instead of touching freed memory. */
#ifndef EVO_SCENE_BACKEND_H
#define EVO_SCENE_BACKEND_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A backend's world, as the scene sees it: each backend casts its own. */
typedef struct evo_bworld evo_bworld;

typedef struct evo_body_id {
	int32_t index; /* 0 based; -1 for none */
	uint16_t generation;
} evo_body_id;

#define EVO_BODY_NONE ((evo_body_id){-1, 0})

typedef enum evo_shape_type {
	EVO_SHAPE_CIRCLE = 0, /* a sphere in 3D */
	EVO_SHAPE_BOX = 1,
	EVO_SHAPE_SEGMENT = 2,	/* 2D only: a static wall of no thickness */
	EVO_SHAPE_CYLINDER = 3, /* 3D only */
} evo_shape_type;

/* A shape of a body (its centre in the body's frame) or a static one
 * (in the world's frame). */
typedef struct evo_bshape {
	evo_shape_type type;
	double pos[3];	    /* centre; a segment's first end */
	double end[3];	    /* a segment's second end */
	double yaw;	    /* turn about z */
	double radius;	    /* circle, sphere, cylinder */
	double half[3];	    /* box: half sides along x, y, z */
	double half_length; /* cylinder */
	int axis;	    /* cylinder: its axis, 0 x, 1 y, 2 z */
	double friction, restitution;
	/* a static's category (Box2D's statics are all EVO_CAT_OBSTACLE);
	 * a body's shapes take the body's */
	uint16_t category;
} evo_bshape;

#define EVO_BODY_MAX_SHAPES 4

typedef struct evo_bbody_def {
	int dynamic;   /* 0: static, never moves */
	int kinematic; /* 2D only: moved by its velocity alone (the mazes) */
	double pos[3];
	double yaw;
	double mass;	/* 3D: kilograms, the first shape gives the inertia */
	double density; /* 2D: kilograms per square metre */
	double linear_damping, angular_damping; /* 2D */
	int allow_sleep;			/* 2D */
	int n_shapes;				/* 2D: 1 */
	evo_bshape shape[EVO_BODY_MAX_SHAPES];
	/* collision categories: two shapes collide when each one's
	 * category is in the other's mask (values are the world's own) */
	uint16_t category, mask;
	/* 3D: shapes of one group (>= 0) never collide with each other and
	 * touching is counted per group; -1: a group of its own */
	int group;
} evo_bbody_def;

/* A body's pose: its centre, its yaw (2D: the angle as the engine keeps
 * it, not wrapped) and R, row-major, turning a vector of the body's
 * frame into the world's (world = R body). */
typedef struct evo_bpose {
	double pos[3];
	double yaw;
	double R[9];
} evo_bpose;

/* The world's settings; each backend's world_def gives its defaults. */
typedef struct evo_bworld_def {
	double step;		    /* seconds per physics step */
	int velocity_iterations;    /* 2D */
	int position_iterations;    /* 2D */
	double gravity;		    /* 3D: m/s^2 along -z */
	double erp, cfm;	    /* 3D: ODE's constraint settings */
	double ground_friction;	    /* 3D */
	double max_speed, max_spin; /* 3D: beyond, a body exploded */
} evo_bworld_def;

/* What step found wrong with a body (3D). */
typedef enum evo_bfault_kind {
	EVO_BFAULT_NAN = 0, /* a position, turn or speed not a number */
	EVO_BFAULT_SPEED,   /* faster than max_speed */
	EVO_BFAULT_SPIN,    /* spinning faster than max_spin */
} evo_bfault_kind;

typedef struct evo_bfault {
	evo_body_id body; /* the first body that exploded */
	evo_bfault_kind kind;
	double value; /* its speed (m/s) or spin (rad/s) */
} evo_bfault;

/* A shape found by query_box, in world coordinates (2D). */
typedef struct evo_shape_info {
	evo_shape_type type;
	uint16_t category;
	double x, y;	     /* centre (a segment's middle) */
	double radius;	     /* circle */
	double vx[4], vy[4]; /* box corners, counter-clockwise; a segment's
				two ends in vx[0..1], vy[0..1] */
	evo_body_id body;    /* EVO_BODY_NONE for static obstacles */
	int obstacle;	     /* the obstacle's index, -1 for a body */
} evo_shape_info;

/* Frames of apply_force_at's force and point. */
#define EVO_BFORCE_BODY 1u /* the force is in the body's frame */
#define EVO_BPOINT_BODY 2u /* the point is in the body's frame */

typedef struct evo_backend {
	const char *name; /* "Box2D", "ODE" */
	int dims;	  /* 2 or 3 */

	evo_bworld_def (*world_def)(void);
	/* NULL when the definition is invalid or memory runs out */
	evo_bworld *(*create)(const evo_bworld_def *def);
	void (*destroy)(evo_bworld *w);
	/* Make the world again: every body with the same id, where and as
	 * it was added, and no statics, joints or contacts. */
	void (*reset)(evo_bworld *w);

	/* EVO_BODY_NONE when the definition is invalid or memory runs out */
	evo_body_id (*add_body)(evo_bworld *w, const evo_bbody_def *def);
	int (*remove_body)(evo_bworld *w, evo_body_id id); /* 0 or -1 */
	int (*valid)(const evo_bworld *w, evo_body_id id);
	/* a disabled body takes no part in collisions, queries or rays */
	void (*set_enabled)(evo_bworld *w, evo_body_id id, int enabled);
	/* 2D: wake a body and restart its time at rest */
	void (*wake)(evo_bworld *w, evo_body_id id);

	/* A static obstacle; its index, or -1 for a size that is not
	 * positive. clear_statics removes them all (indices start again).
	 * Box2D keeps its own frictions: 0, and 1 for segments. */
	int (*add_static)(evo_bworld *w, const evo_bshape *s);
	void (*clear_statics)(evo_bworld *w);

	evo_bpose (*pose)(const evo_bworld *w, evo_body_id id);
	void (*set_pose)(evo_bworld *w, evo_body_id id, const double pos[3],
			 double yaw);
	void (*velocity)(const evo_bworld *w, evo_body_id id, double v[3],
			 double omega[3]);
	void (*set_velocity)(evo_bworld *w, evo_body_id id, const double v[3],
			     const double omega[3]);
	/* A force (newtons) at a point, for the next step; frames: the
	 * EVO_BFORCE_BODY / EVO_BPOINT_BODY bits, 0 for both in the world
	 * (2D: 0 only). */
	void (*apply_force_at)(evo_bworld *w, evo_body_id id, const double f[3],
			       const double at[3], unsigned frames);
	void (*add_torque)(evo_bworld *w, evo_body_id id, const double t[3]);

	/* 2D only: weld b to a where they are now (the claw's grip); a
	 * joint id >= 0 or -1. */
	int (*weld)(evo_bworld *w, evo_body_id a, evo_body_id b);
	void (*unweld)(evo_bworld *w, int joint);
	/* 3D only: a hinge at a world point about a world axis (its index
	 * or -1), and its motor for the next step: a torque (N m), or a
	 * target rate (rad/s) reached with at most fmax; its rate now. */
	int (*hinge)(evo_bworld *w, evo_body_id a, evo_body_id b,
		     const double anchor[3], const double axis[3]);
	void (*hinge_torque)(evo_bworld *w, int hinge, double torque);
	void (*hinge_velocity)(evo_bworld *w, int hinge, double rate,
			       double fmax);
	double (*hinge_rate)(const evo_bworld *w, int hinge);

	/* The nearest hit of the ray from `from` along the unit vector dir,
	 * up to len, among shapes whose category is in mask, ignoring the
	 * body ignore (2D) or the group ignore_group (3D): its distance, or
	 * -1. */
	double (*raycast)(evo_bworld *w, const double from[3],
			  const double dir[3], double len, uint16_t mask,
			  evo_body_id ignore, int ignore_group);
	/* 2D only: the shapes whose bounding boxes overlap the box lo..hi
	 * (x and y), in the engine's order; writes at most cap and returns
	 * how many there are. */
	int (*query_box)(const evo_bworld *w, const double lo[3],
			 const double hi[3], uint16_t mask, evo_shape_info *out,
			 int cap);

	/* What a body touches now: how many bodies or statics. */
	int (*touching)(const evo_bworld *w, evo_body_id id);
	/* 1 when body id touches body other, or the static of index
	 * `obstacle` (add_static's): in 2D now, in 3D in any step since
	 * forget_touches (3D only: a scene calls it as a tick begins, so
	 * that a touch in any of the tick's substeps counts; a world keeps
	 * these touches only once it has been called). */
	int (*touching_body)(const evo_bworld *w, evo_body_id id,
			     evo_body_id other);
	int (*touching_obstacle)(const evo_bworld *w, evo_body_id id,
				 int obstacle);
	void (*forget_touches)(evo_bworld *w);
	/* 2D only: 1 when body id lies closer than its size to what its
	 * mask takes (a kinematic body's step to undo, docs/world.md). */
	int (*blocked)(const evo_bworld *w, evo_body_id id);

	/* One physics step: 0, or -1 when a body exploded (3D), with
	 * *fault saying which and how; the world must then be made again. */
	int (*step)(evo_bworld *w, evo_bfault *fault);
} evo_backend;

#ifdef __cplusplus
}
#endif

#endif
