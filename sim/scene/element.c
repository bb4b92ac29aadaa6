/* The elements of either world (sim/scene/element.h): their defaults, and
 * the checks and storage of an add that the 2D and 3D scenes share. */
#include "scene/element.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "base/number.h"

evo_element_def evo_default_element_def(evo_piece_kind kind, unsigned dim)
{
	evo_element_def d;
	memset(&d, 0, sizeof d);
	d.kind = kind;
	if (dim == EVO_DIM_2D) {
		d.size = 1.0;
		d.half_w = d.half_h = 1.0;
		d.density = 2.0;
		d.linear_damping = 5.0;
		d.angular_damping = 5.0;
		return d;
	}
	d.half[0] = d.half[1] = d.half[2] = 0.5;
	d.radius = 0.5;
	d.half_length = 0.5;
	d.mass = 1;
	d.friction = 0.5;
	d.sphere = 1;
	return d;
}

static int positive(double v)
{
	return isfinite(v) && v > 0;
}

/* Whether d's size is its half sides (a box; in 3D a zone and a box
 * object too) rather than its radius. */
static int has_sides(const evo_element_def *d, unsigned dim)
{
	if (d->kind == EVO_PIECE_BOX)
		return 1;
	return dim == EVO_DIM_3D &&
	       (d->kind == EVO_PIECE_ZONE ||
		(d->kind == EVO_PIECE_OBJECT && !d->sphere));
}

/* 0 when d is an element world dim can add, or -1 with err set. */
static int check(const evo_element_def *d, unsigned dim, evo_err *err)
{
	const char *world = dim == EVO_DIM_2D ? "2D" : "3D";
	if ((unsigned)d->kind > EVO_PIECE_LAST_ELEMENT)
		return evo_fail(err, "element: unknown kind %d", (int)d->kind);
	const evo_kind_row *row = evo_piece_kind_row(d->kind);
	if (!(row->dims & dim))
		return evo_fail(err,
				"element: a %s is no element of the %s "
				"world",
				row->name, world);
	double v[] = {d->pos[0], d->pos[1],  d->pos[2],	 d->angle,
		      d->size,	 d->half[0], d->half[1], d->half[2]};
	if (!evo_finite_all(v, (int)(sizeof v / sizeof v[0])))
		return evo_fail(err, "element: a value is not a number");
	int axes = dim == EVO_DIM_2D ? 2 : 3;
	if (has_sides(d, dim)) {
		for (int k = 0; k < axes; k++)
			if (!(d->half[k] > 0))
				return evo_fail(err, "a box's half sides must "
						     "be > 0");
	} else if (!(d->size > 0)) {
		return evo_fail(err, d->kind == EVO_PIECE_ZONE
					 ? "a zone's half side must be > 0"
					 : "a radius must be > 0");
	}
	if (dim == EVO_DIM_3D && d->kind == EVO_PIECE_CYLINDER &&
	    !positive(d->half_length))
		return evo_fail(err, "a cylinder's height must be > 0");
	if (dim == EVO_DIM_3D && d->kind == EVO_PIECE_OBJECT &&
	    !positive(d->mass))
		return evo_fail(err, "an object's mass must be > 0");
	return 0;
}

evo_element *evo_element_store(evo_element **arr, int *cap, int n,
			       const evo_element_def *d, unsigned dim,
			       const char *dflt, evo_err *err)
{
	if (check(d, dim, err))
		return NULL;
	if (d->name && d->name[0] &&
	    evo_store_find(*arr, n, sizeof **arr, offsetof(evo_element, name),
			   d->name) >= 0) {
		evo_fail(err, "element '%s' is defined twice", d->name);
		return NULL;
	}
	evo_element *e = evo_store_add((void **)arr, cap, n, sizeof *e, err);
	if (!e || evo_store_name(e->name, d->name, dflt, n, err))
		return NULL;
	e->kind = d->kind;
	e->def = *d;
	e->def.name = NULL;
	memcpy(e->pos, d->pos, sizeof e->pos);
	e->angle = d->angle;
	e->size = d->size;
	memcpy(e->half, d->half, sizeof e->half);
	e->active = 1;
	e->held_by = -1;
	e->body = EVO_BODY_NONE;
	e->obstacle = -1;
	return e;
}
