/* evo — the shapes around a 2D bot and what its proximity sensors read of
 * them (sensors_internal.h): one area query for the box that holds a
 * bot's fans, and each ray intersected with those few shapes here.
 *
 * Proximity sensors are the costly ones: BotType8 carries ten of them with
 * nine rays each, and a Box2D ray cast through the world's tree costs
 * about 25 µs a tick for those 90 rays. So the bot asks Box2D once for the
 * shapes around it (evo_shapes_gather) and every ray is intersected with
 * those shapes here, with the same arithmetic as Box2D's own ray casts
 * (in double): the readings agree with evo_world_raycast to float
 * precision (tests/sim/world2d/test_sensors.c checks it on random
 * scenes). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "world2d/scene_internal.h"
#include "world2d/sensors_internal.h"

/* ---- the shapes around the bot ---------------------------------------- */

/* One area query for the box `area`, keeping what the bot's rays may
 * see. */
void evo_shapes_gather(const evo_scene *sc, const evo_bot *b,
		       const sense_box *area, uint16_t mask, shape_set *set)
{
	double x0 = area->x0, y0 = area->y0;
	double x1 = area->x1, y1 = area->y1;
	set->s = set->local;
	int n =
	    evo_scene_query(sc, x0, y0, x1, y1, mask, set->local, QUERY_CAP);
	if (n > QUERY_CAP) {
		evo_shape_info *big = malloc((size_t)n * sizeof *big);
		if (big) {
			set->s = big;
			n = evo_scene_query(sc, x0, y0, x1, y1, mask, big, n);
		} else {
			n = QUERY_CAP; /* out of memory: see what fits */
		}
	}
	int kept = 0;
	for (int i = 0; i < n; i++) {
		evo_shape_info *s = &set->s[i];
		if (unseen(sc, b, s->body))
			continue;
		bound_radius(s);
		set->s[kept++] = *s;
	}
	set->n = kept;
}

void evo_shapes_release(shape_set *set)
{
	if (set->s != set->local)
		free(set->s);
	set->s = set->local;
	set->n = 0;
}

/* What a proximity sensor's rays can reach, as a box in world
 * coordinates added to `area`: the fan from the sensor's point, its two
 * edge rays' ends and, where the fan spans one, the points straight along
 * an axis, `range` away (a fan of half a turn or more: the square around
 * its point). Every ray lies in the fan and so in the box; the
 * world's broad phase is then asked for this box, not for the square
 * around the bot that holds every direction (a forward fan of 120
 * degrees covers a third of it). A little margin keeps a shape that only
 * touches the box's edge after rounding to Box2D's floats. */
void evo_fan_box(const evo_sensor *se, const sense_frame *f, sense_box *area)
{
	const evo_sensor_def *d = &se->def;
	int n = d->rays < 1 ? 1 : d->rays;
	n = n > EVO_PROX_MAX_RAYS ? EVO_PROX_MAX_RAYS : n;
	double px, py;
	to_world(f, d->x, d->y, &px, &py);
	box_add(area, px, py);
	double arc = n > 1 ? fabs(d->arc) : 0;
	double r = d->range;
	if (arc >= M_PI / 2) {
		box_add(area, px - r, py - r);
		box_add(area, px + r, py + r);
	} else {
		/* the first and last rays' directions in the world (the
		 * fan turns anticlockwise from the first, by less than half
		 * a turn), and each axis direction between them: e is
		 * between when it is left of the first and right of the
		 * last */
		double ux = f->c * se->ray_c[0] - f->s * se->ray_s[0];
		double uy = f->s * se->ray_c[0] + f->c * se->ray_s[0];
		double vx = f->c * se->ray_c[n - 1] - f->s * se->ray_s[n - 1];
		double vy = f->s * se->ray_c[n - 1] + f->c * se->ray_s[n - 1];
		box_add(area, px + r * ux, py + r * uy);
		box_add(area, px + r * vx, py + r * vy);
		static const double ax[4] = {1, 0, -1, 0},
				    ay[4] = {0, 1, 0, -1};
		for (int k = 0; k < 4; k++)
			if (ux * ay[k] - uy * ax[k] > 0 &&
			    ax[k] * vy - ay[k] * vx > 0)
				box_add(area, px + r * ax[k], py + r * ay[k]);
	}
	const double margin = 1e-3 * (1 + r);
	area->x0 -= margin;
	area->y0 -= margin;
	area->x1 += margin;
	area->y1 += margin;
}

/* ---- proximity: rays against circles and boxes ------------------------ */

/* The segment p -> p + d against a circle, as b2CircleShape::RayCast
 * does it: the fraction of the first crossing of the rim if it lies in
 * [0, max], else max. A segment that starts inside sees nothing. rr is
 * d's squared length, the same for every shape a ray meets. */
static double ray_circle(const evo_shape_info *s, double px, double py,
			 double dx, double dy, double rr, double max)
{
	double sx = px - s->x, sy = py - s->y;
	double b = sx * sx + sy * sy - s->radius * s->radius;
	double c = sx * dx + sy * dy;
	/* Inside, or outside and heading away: no crossing ahead. */
	if (b < 0 || c > 0)
		return max;
	double sigma = c * c - rr * b;
	if (sigma < 0)
		return max;
	double a = -(c + sqrt(sigma));
	return a <= max * rr ? a / rr : max;
}

/* The segment against a box given by its corners counter-clockwise (in
 * Box2D's sense), clipping against each edge's half plane as
 * b2PolygonShape::RayCast does. Box2D 2.4 casts against the bare polygon,
 * without its skin (b2_polygonRadius), and so does this. */
static double ray_box(const evo_shape_info *s, double px, double py, double dx,
		      double dy, double max)
{
	double lower = 0, upper = max;
	int entered = 0;
	for (int i = 0; i < 4; i++) {
		int j = (i + 1) & 3;
		/* Outward normal of edge i -> j, not normalised: only the
		 * ratio of the two dot products counts. */
		double nx = s->vy[j] - s->vy[i], ny = s->vx[i] - s->vx[j];
		double num = nx * (s->vx[i] - px) + ny * (s->vy[i] - py);
		double den = nx * dx + ny * dy;
		if (den == 0) {
			if (num < 0)
				return max; /* parallel and outside */
		} else if (den < 0 && num < lower * den) {
			lower = num / den;
			entered = 1;
		} else if (den > 0 && num < upper * den) {
			upper = num / den;
		}
		if (upper < lower)
			return max;
	}
	return entered ? lower : max;
}

/* The segment p -> p + d against a wall (a segment a -> b, both of its
 * sides), as b2EdgeShape::RayCast does: where the ray's line meets the
 * wall's line, if that lies within [0, max] of the ray and within the wall,
 * ends included. */
static double ray_segment(const evo_shape_info *s, double px, double py,
			  double dx, double dy, double max)
{
	double ex = s->vx[1] - s->vx[0], ey = s->vy[1] - s->vy[0];
	/* the wall's normal, not normalised: t is a ratio */
	double nx = ey, ny = -ex;
	double num = nx * (s->vx[0] - px) + ny * (s->vy[0] - py);
	double den = nx * dx + ny * dy;
	if (den == 0)
		return max; /* parallel */
	double t = num / den;
	if (t < 0 || t > max)
		return max;
	double qx = px + t * dx - s->vx[0], qy = py + t * dy - s->vy[0];
	double u = (qx * ex + qy * ey) / (ex * ex + ey * ey);
	return u >= 0 && u <= 1 ? t : max;
}

/* The n rays p -> p + d[i] against shape s, each keeping the nearer of
 * its best so far and its crossing. The shape's kind is looked at once,
 * not once a ray: a loop of one kind each, which the compiler inlines. */
static void rays_shape(const evo_shape_info *s, double px, double py,
		       const double *dx, const double *dy, const double *rr,
		       double *best, int n)
{
	switch (s->type) {
	case EVO_SHAPE_CIRCLE:
		for (int i = 0; i < n; i++)
			best[i] = ray_circle(s, px, py, dx[i], dy[i], rr[i],
					     best[i]);
		return;
	case EVO_SHAPE_SEGMENT:
		for (int i = 0; i < n; i++)
			best[i] = ray_segment(s, px, py, dx[i], dy[i], best[i]);
		return;
	case EVO_SHAPE_BOX:
	case EVO_SHAPE_CYLINDER: /* 3D only: never in a 2D world */
		break;
	}
	for (int i = 0; i < n; i++)
		best[i] = ray_box(s, px, py, dx[i], dy[i], best[i]);
}

/* Ray i's direction in the world, range long: the sensor's own direction
 * in the bot's frame (worked out once, evo_scene_add_sensor) turned with
 * the bot. */
static void ray_dir(const evo_sensor *se, const sense_frame *f, int i,
		    double *dx, double *dy)
{
	double range = se->def.range;
	*dx = (f->c * se->ray_c[i] - f->s * se->ray_s[i]) * range;
	*dy = (f->s * se->ray_c[i] + f->c * se->ray_s[i]) * range;
}

/* Whether shape s's bounding circle may meet the fan from p whose edge
 * rays are (fx, fy) and (lx, ly): not too far, not behind, not beyond
 * either edge ray. The edge test holds while the fan is convex (spans
 * less than half a turn). */
static int may_meet(const evo_shape_info *s, const evo_sensor_def *d, double px,
		    double py, int convex, double fx, double fy, double lx,
		    double ly)
{
	if (!(s->category & d->mask))
		return 0;
	double ox = s->x - px, oy = s->y - py;
	double lim = d->range + s->radius;
	if (ox * ox + oy * oy > lim * lim)
		return 0;
	if (!convex)
		return 1;
	/* Each test is scaled by range (the rays are range long), and so
	 * is its bound. */
	double rr = s->radius * d->range;
	/* (fx + lx, fy + ly) is at most 2 range long. */
	if (ox * (fx + lx) + oy * (fy + ly) < -2 * rr)
		return 0;
	/* Outward normals: the first edge rotated by -90 degrees, the last
	 * one by +90. */
	return !(ox * fy - oy * fx > rr || oy * lx - ox * ly > rr);
}

/* A proximity sensor against the shapes of set. Most of a tick's fans
 * meet no shape: only the edge rays are worked out for the culling, the
 * others once a shape passes it. */
double evo_proximity_sample(evo_sensor *se, const sense_frame *f,
			    const shape_set *set)
{
	const evo_sensor_def *d = &se->def;
	int n = d->rays < 1 ? 1 : d->rays;
	n = n > EVO_PROX_MAX_RAYS ? EVO_PROX_MAX_RAYS : n;
	double arc = n > 1 ? fabs(d->arc) : 0;
	double px, py;
	to_world(f, d->x, d->y, &px, &py);

	double fx, fy, lx, ly;
	ray_dir(se, f, 0, &fx, &fy);
	ray_dir(se, f, n - 1, &lx, &ly);
	int convex = 2 * arc < M_PI;
	double dx[EVO_PROX_MAX_RAYS], dy[EVO_PROX_MAX_RAYS];
	double rr[EVO_PROX_MAX_RAYS], best[EVO_PROX_MAX_RAYS];
	int met = 0;
	for (int k = 0; k < set->n; k++) {
		const evo_shape_info *s = &set->s[k];
		if (!may_meet(s, d, px, py, convex, fx, fy, lx, ly))
			continue;
		if (!met) {
			for (int i = 0; i < n; i++) {
				ray_dir(se, f, i, &dx[i], &dy[i]);
				rr[i] = dx[i] * dx[i] + dy[i] * dy[i];
				best[i] = 1;
			}
			met = 1;
		}
		rays_shape(s, px, py, dx, dy, rr, best, n);
	}

	/* Rays past n keep the 1 evo_scene_add_sensor gave them. */
	double nearest = 1;
	if (!met) {
		for (int i = 0; i < n; i++)
			se->ray[i] = 1;
	}
	for (int i = 0; i < n && met; i++) {
		se->ray[i] = (float)best[i];
		nearest = best[i] < nearest ? best[i] : nearest;
	}
	return nearest < d->deadzone ? 0 : clamp01(nearest);
}

/* How far from the bot's centre a proximity sensor's rays can reach. */
static double sensor_reach(const evo_sensor_def *d)
{
	return sqrt(d->x * d->x + d->y * d->y) + d->range;
}

/* The box that holds every fan of a bot's proximity sensors, and the
 * union of what they see (0: no proximity sensor reads anything). A bot
 * with sensors all around (BotType8's ten) gets the square around it
 * that holds every direction, worked out at less cost; one with one or
 * two fans, their boxes. */
uint16_t evo_sense_area(const evo_bot *b, const sense_frame *f, sense_box *area)
{
	uint16_t mask = 0;
	int n = 0;
	double reach = 0, bump = 0;
	for (int i = 0; i < b->n_sensors; i++) {
		const evo_sensor *se = &b->sensor[i];
		if (se->def.kind == EVO_SENSE_BUMPER && !se->idle) {
			bump = se->def.reach > bump ? se->def.reach : bump;
			mask |= se->def.mask;
		}
		if (se->def.kind != EVO_SENSE_PROXIMITY || se->idle)
			continue;
		double r = sensor_reach(&se->def);
		reach = r > reach ? r : reach;
		mask |= se->def.mask;
		n++;
	}
	if (n > 2) {
		reach = reach > bump ? reach : bump;
		area->x0 = f->x - reach;
		area->y0 = f->y - reach;
		area->x1 = f->x + reach;
		area->y1 = f->y + reach;
		return mask;
	}
	area->x0 = area->y0 = INFINITY;
	area->x1 = area->y1 = -INFINITY;
	for (int i = 0; i < b->n_sensors; i++) {
		const evo_sensor *se = &b->sensor[i];
		if (se->def.kind == EVO_SENSE_PROXIMITY && !se->idle)
			evo_fan_box(se, f, area);
	}
	if (bump > 0) {
		/* bumpers: the square around the bot they reach */
		box_add(area, f->x - bump, f->y - bump);
		box_add(area, f->x + bump, f->y + bump);
	}
	return mask;
}
