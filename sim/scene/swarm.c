/* The swarm sensors over a bot's pose, the scene's lights and patches, the
 * other bots and the backend's rays (sim/scene/swarm.h), the same in 2D
 * and 3D. */
#include "scene/swarm.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/store.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* ---- storage ------------------------------------------------------------ */

static int finite_n(const double *v, int n)
{
	for (int i = 0; i < n; i++)
		if (!isfinite(v[i]))
			return 0;
	return 1;
}

/* Item, of size `size`, at the end of *arr (*n items, room for *cap,
 * as evo_store_add grows it): the item's index, or -1 with err set. */
static int append(void **arr, int *n, int *cap, const void *item, size_t size,
		  evo_err *err)
{
	void *slot = evo_store_add(arr, cap, *n, size, err);
	if (!slot)
		return -1;
	memcpy(slot, item, size);
	return (*n)++;
}

int evo_swarm_add_light(evo_swarm *w, const evo_light *l, evo_err *err)
{
	if (!finite_n(l->pos, 3) || !isfinite(l->intensity))
		return evo_fail(err, "light: a value is not a number");
	if (!(l->intensity > 0))
		return evo_fail(err,
				"light: intensity must be above 0, found %g",
				l->intensity);
	return append((void **)&w->light, &w->n_lights, &w->cap_lights, l,
		      sizeof *l, err);
}

int evo_swarm_add_patch(evo_swarm *w, const evo_patch *p, evo_err *err)
{
	double v[] = {p->x, p->y, p->yaw, p->hx, p->hy, p->radius, p->grey};
	if (!finite_n(v, 7))
		return evo_fail(err, "patch: a value is not a number");
	if (p->circle ? !(p->radius > 0) : !(p->hx > 0 && p->hy > 0))
		return evo_fail(err, "patch: %s must be above 0",
				p->circle ? "radius" : "hx and hy");
	if (!(p->grey >= 0 && p->grey <= 1))
		return evo_fail(err, "patch: grey must be in [0, 1], found %g",
				p->grey);
	return append((void **)&w->patch, &w->n_patches, &w->cap_patches, p,
		      sizeof *p, err);
}

static const char *const colour_names[EVO_COLOUR_COUNT] = {
    "red", "yellow", "green", "cyan", "blue", "magenta", "white", "black"};

const char *evo_colour_name(int colour)
{
	return colour >= 0 && colour < EVO_COLOUR_COUNT ? colour_names[colour]
							: NULL;
}

int evo_colour_by_name(const char *name)
{
	for (int k = 0; name && k < EVO_COLOUR_COUNT; k++)
		if (strcmp(name, colour_names[k]) == 0)
			return k;
	return -1;
}

int evo_swarm_set_colour(evo_swarm *w, evo_blob_kind kind, int index,
			 int colour, evo_err *err)
{
	if (!evo_colour_name(colour))
		return evo_fail(err, "no colour %d", colour);
	for (int i = 0; i < w->n_blobs; i++)
		if (w->blob[i].kind == kind && w->blob[i].index == index) {
			w->blob[i].colour = colour;
			return i;
		}
	evo_blob b = {kind, index, colour};
	return append((void **)&w->blob, &w->n_blobs, &w->cap_blobs, &b,
		      sizeof b, err);
}

void evo_swarm_free(evo_swarm *w)
{
	free(w->light);
	free(w->patch);
	free(w->blob);
	memset(w, 0, sizeof *w);
}

evo_swarm_sensor evo_default_swarm_sensor(double range)
{
	evo_swarm_sensor s;
	memset(&s, 0, sizeof s);
	s.aperture = M_PI / 4;
	s.range = range;
	s.slot = 1;
	s.read = EVO_RAB_RANGE;
	s.scale = 10;
	s.colour = -1;
	return s;
}

int evo_swarm_check_sensor(const evo_swarm_sensor *s, const char *name,
			   evo_err *err)
{
	name = name ? name : "?";
	double v[] = {s->aperture, s->range, s->scale};
	if (!finite_n(v, 3))
		return evo_fail(err, "sensor '%s': a value is not a number",
				name);
	if (!(s->aperture >= 0))
		return evo_fail(err, "sensor '%s': aperture must be 0 or more",
				name);
	if (!(s->range > 0) || !(s->scale > 0))
		return evo_fail(err,
				"sensor '%s': range and scale must be above "
				"0, found %g and %g",
				name, s->range, s->scale);
	if (s->slot < 1 || s->slot > EVO_SWARM_MAX_SLOTS)
		return evo_fail(err, "sensor '%s': slot must be 1 to %d", name,
				EVO_SWARM_MAX_SLOTS);
	if ((unsigned)s->read >= EVO_RAB_READ_COUNT)
		return evo_fail(err, "sensor '%s': unknown reading %d", name,
				(int)s->read);
	if (s->colour < -1 || s->colour >= EVO_COLOUR_COUNT)
		return evo_fail(err, "sensor '%s': no colour %d", name,
				s->colour);
	if (s->index < 0 || s->index >= EVO_SWARM_MAX_VALUES)
		return evo_fail(err, "sensor '%s': index must be 1 to %d", name,
				EVO_SWARM_MAX_VALUES);
	return 0;
}

/* ---- frames ---------------------------------------------------------------
 */

evo_swarm_frame evo_swarm_frame_2d(double x, double y, double angle)
{
	double c = cos(angle), s = sin(angle);
	evo_swarm_frame f = {{x, y, 0}, {c, -s, 0, s, c, 0, 0, 0, 1}};
	return f;
}

/* A point of the bot's frame in the world's. */
static void to_world(const evo_swarm_frame *f, const double b[3], double w[3])
{
	for (int i = 0; i < 3; i++)
		w[i] = f->pos[i] + f->R[3 * i] * b[0] + f->R[3 * i + 1] * b[1] +
		       f->R[3 * i + 2] * b[2];
}

/* A vector of the world's frame in the bot's (R's transpose). */
static void to_body(const evo_swarm_frame *f, const double v[3], double b[3])
{
	for (int i = 0; i < 3; i++)
		b[i] = f->R[i] * v[0] + f->R[3 + i] * v[1] + f->R[6 + i] * v[2];
}

double evo_wrap_angle(double a)
{
	a = fmod(a, 2 * M_PI);
	if (a > M_PI)
		a -= 2 * M_PI;
	else if (a <= -M_PI)
		a += 2 * M_PI;
	return a;
}

/* The bearing of world vector d in the bot's horizontal plane. */
static double bearing(const evo_swarm_frame *f, const double d[3])
{
	double b[3];
	to_body(f, d, b);
	return atan2(b[1], b[0]);
}

/* 1 when an obstacle cuts the straight line from p along unit u before
 * len (a hair short of it: the light or bot at its end is not an
 * obstacle, and a wall exactly through it does not hide it). */
static int occluded(const evo_swarm_rays *rays, const double p[3],
		    const double u[3], double len)
{
	if (!rays || !rays->be || len <= 1e-9)
		return 0;
	double h = rays->be->raycast(rays->bw, p, u, len, rays->mask,
				     rays->ignore, rays->ignore_group);
	return h >= 0 && h < len * (1 - 1e-9);
}

/* ---- light ----------------------------------------------------------------
 */

double evo_swarm_light(const evo_swarm *w, const evo_swarm_frame *f,
		       const double at[3], double yaw, double aperture,
		       const evo_swarm_rays *rays)
{
	double p[3];
	to_world(f, at, p);
	double sum = 0;
	for (int i = 0; i < w->n_lights && sum < 1; i++) {
		const evo_light *l = &w->light[i];
		double d[3] = {l->pos[0] - p[0], l->pos[1] - p[1],
			       l->pos[2] - p[2]};
		double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
		if (dd <= 0) {
			sum = 1; /* the sensor sits in the light */
			break;
		}
		if (fabs(evo_wrap_angle(bearing(f, d) - yaw)) > aperture)
			continue;
		double len = sqrt(dd);
		double u[3] = {d[0] / len, d[1] / len, d[2] / len};
		if (occluded(rays, p, u, len))
			continue;
		double r = l->intensity / dd;
		sum += r < 1 ? r : 1;
	}
	return sum < 1 ? sum : 1;
}

/* ---- ground ---------------------------------------------------------------
 */

static int patch_holds(const evo_patch *pa, double x, double y)
{
	double dx = x - pa->x, dy = y - pa->y;
	if (pa->circle)
		return dx * dx + dy * dy <= pa->radius * pa->radius;
	double c = cos(pa->yaw), s = sin(pa->yaw);
	double lx = c * dx + s * dy, ly = -s * dx + c * dy;
	return fabs(lx) <= pa->hx && fabs(ly) <= pa->hy;
}

double evo_swarm_ground(const evo_swarm *w, const evo_swarm_frame *f,
			const double at[3])
{
	double p[3];
	to_world(f, at, p);
	for (int i = w->n_patches - 1; i >= 0; i--)
		if (patch_holds(&w->patch[i], p[0], p[1]))
			return w->patch[i].grey;
	return EVO_SWARM_FLOOR;
}

/* ---- range and bearing ------------------------------------------------------
 */

/* The `slot` nearest neighbours heard, nearest first. */
typedef struct ranked {
	int n, count;
	double dist[EVO_SWARM_MAX_SLOTS];
	evo_swarm_peer peer[EVO_SWARM_MAX_SLOTS];
} ranked;

/* Put peer p at distance d among the kept ones; bots come in index order,
 * so a tie keeps the one already there first. */
static void rank(ranked *r, int keep, const evo_swarm_peer *p, double d)
{
	r->count++;
	int at = r->n;
	while (at > 0 && r->dist[at - 1] > d)
		at--;
	if (at >= keep)
		return;
	int last = r->n < keep ? r->n : keep - 1;
	for (int k = last; k > at; k--) {
		r->dist[k] = r->dist[k - 1];
		r->peer[k] = r->peer[k - 1];
	}
	r->dist[at] = d;
	r->peer[at] = *p;
	if (r->n < keep)
		r->n++;
}

static double clamp01(double v)
{
	if (!(v >= 0))
		return 0;
	return v > 1 ? 1 : v;
}

/* The reading of s->read about the ranked ones; a camera's peers carry
 * their colour's reading as value 0. */
static double answer(const evo_swarm_sensor *s, const evo_swarm_frame *f,
		     const ranked *r)
{
	if (s->read == EVO_RAB_COUNT)
		return clamp01(r->count / s->scale);
	if (r->n < s->slot)
		return s->read == EVO_RAB_RANGE	    ? 1
		       : s->read == EVO_RAB_BEARING ? 0.5
						    : 0;
	const evo_swarm_peer *p = &r->peer[s->slot - 1];
	switch (s->read) {
	case EVO_RAB_RANGE:
		return clamp01(r->dist[s->slot - 1] / s->range);
	case EVO_RAB_BEARING: {
		double d[3] = {p->pos[0] - f->pos[0], p->pos[1] - f->pos[1],
			       p->pos[2] - f->pos[2]};
		double a = bearing(f, d);
		if (a <= -M_PI)
			a = M_PI; /* straight behind reads 1, as bearings do */
		return clamp01(0.5 + a / (2 * M_PI));
	}
	case EVO_RAB_VALUE:
		return s->index < p->n_values ? clamp01(p->value[s->index]) : 0;
	case EVO_RAB_COLOUR:
		return p->n_values > 0 ? p->value[0] : 0;
	case EVO_RAB_COUNT:
	case EVO_RAB_READ_COUNT:
		break;
	}
	return 0;
}

/* Rank p if it lies within range of f's centre and, with occlusion, in
 * sight of it: no obstacle nearer than reach short of it. */
static void consider(ranked *r, const evo_swarm_sensor *s,
		     const evo_swarm_frame *f, const evo_swarm_peer *p,
		     double reach, const evo_swarm_rays *rays)
{
	double d[3] = {p->pos[0] - f->pos[0], p->pos[1] - f->pos[1],
		       p->pos[2] - f->pos[2]};
	double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
	if (!(len <= s->range))
		return;
	if (s->occluded && len > reach) {
		double u[3] = {d[0] / len, d[1] / len, d[2] / len};
		/* a body's own rim is no obstacle: short of it by a margin
		 * past a float engine's rounding */
		double free = reach > 0 ? (len - reach) * (1 - 1e-4) : len;
		if (occluded(rays, f->pos, u, free))
			return;
	}
	rank(r, s->read == EVO_RAB_COUNT ? 1 : s->slot, p, len);
}

double evo_swarm_rab(const evo_swarm_sensor *s, const evo_swarm_frame *f,
		     int self, int n, evo_swarm_peer_fn peer, void *ctx,
		     const evo_swarm_rays *rays)
{
	ranked r;
	r.n = r.count = 0;
	for (int i = 0; i < n; i++) {
		evo_swarm_peer p;
		if (i != self && peer(ctx, i, &p))
			consider(&r, s, f, &p, 0, rays);
	}
	return answer(s, f, &r);
}

/* ---- the omnidirectional camera --------------------------------------------
 */

double evo_swarm_camera(const evo_swarm *w, const evo_swarm_sensor *s,
			const evo_swarm_frame *f, int self,
			evo_swarm_where_fn where, void *ctx,
			const evo_swarm_rays *rays)
{
	ranked r;
	r.n = r.count = 0;
	for (int i = 0; i < w->n_blobs; i++) {
		const evo_blob *b = &w->blob[i];
		if ((s->colour >= 0 && b->colour != s->colour) ||
		    (b->kind == EVO_BLOB_BOT && b->index == self))
			continue;
		evo_swarm_peer p;
		double reach = 0;
		if (b->kind == EVO_BLOB_LIGHT) {
			if (b->index < 0 || b->index >= w->n_lights)
				continue;
			memcpy(p.pos, w->light[b->index].pos, sizeof p.pos);
		} else if (!where(ctx, b, p.pos, &reach)) {
			continue;
		}
		p.n_values = 1;
		p.value[0] = (b->colour + 1.0) / EVO_COLOUR_COUNT;
		consider(&r, s, f, &p, reach, rays);
	}
	return answer(s, f, &r);
}
