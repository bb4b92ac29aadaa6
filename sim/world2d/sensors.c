/* evo — the sensors of a bot (sim/world2d/scene.h): each one samples the scene and
 * gives a value in [0, 1]; booleans read EVO_FALSE or EVO_TRUE.
 *
 * Proximity sensors are the costly ones: BotType8 carries ten of them with
 * nine rays each, and a Box2D ray cast through the world's tree costs
 * about 25 µs a tick for those 90 rays. So evo_bot_sense asks Box2D once
 * for the shapes around the bot and intersects every ray with those few
 * shapes here, with the same arithmetic as Box2D's own ray casts (in
 * double): the readings agree with evo_world_raycast to float precision
 * (tests/sim/world2d/test_sensors.c checks it on random scenes). */
#include "world2d/sensors.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "world2d/query.h"
#include "world2d/scene_internal.h"

/* Shapes kept on the stack for one query; a crowd larger than this goes
 * to the heap. */
#define QUERY_CAP 64

/* The bot's pose, with its rotation worked out once for every sensor. */
typedef struct frame {
	double x, y, c, s;
} frame;

/* What a bot's proximity rays can hit this tick. For a box, `radius`
 * holds its bounding radius, which the culling uses. */
typedef struct shape_set {
	evo_shape_info *s;
	int n;
	evo_shape_info local[QUERY_CAP];
} shape_set;

/* A sample into [0, 1] by the one rule for sensor values (docs/mind.md,
 * "Sensor values"; core's evo_q16_from_sensor, which world2d does not
 * see): below 0 reads 0, above 1 reads 1, NaN reads 0.5, the neutral
 * value. No sensor's geometry gives NaN from the finite definitions the
 * scene accepts; a world whose bodies' positions overflowed could. */
static double clamp01(double v)
{
	if (v != v)
		return 0.5;
	if (v > 1)
		return 1;
	return v >= 0 ? v : 0;
}

static double boolean(int v)
{
	return v ? EVO_TRUE : EVO_FALSE;
}

static int same_body(evo_body_id a, evo_body_id b)
{
	return a.index == b.index && a.generation == b.generation;
}

static frame bot_frame(const evo_bot *b)
{
	frame f = {b->x, b->y, b->c, b->s};
	return f;
}

static void to_world(const frame *f, double bx, double by, double *wx,
		     double *wy)
{
	*wx = f->x + f->c * bx - f->s * by;
	*wy = f->y + f->s * bx + f->c * by;
}

/* ---- proximity: the shapes around the bot ----------------------------- */

/* A bot's rays never see its own body, nor an object one of its claws
 * holds: the object sits right before the claw and would blind every
 * forward sensor while carried. */
static int unseen(const evo_scene *sc, const evo_bot *b, evo_body_id id)
{
	if (id.index < 0)
		return 0;
	if (same_body(id, b->body))
		return 1;
	for (int i = 0; i < b->n_actuators; i++) {
		int held = b->actuator[i].held;
		if (b->actuator[i].def.kind == EVO_ACTUATOR_CLAW && held >= 0 &&
		    held < sc->n_elements &&
		    same_body(id, sc->element[held].body))
			return 1;
	}
	return 0;
}

/* An axis-aligned box in world coordinates. */
typedef struct box {
	double x0, y0, x1, y1;
} box;

static void box_add(box *b, double x, double y)
{
	b->x0 = x < b->x0 ? x : b->x0;
	b->y0 = y < b->y0 ? y : b->y0;
	b->x1 = x > b->x1 ? x : b->x1;
	b->y1 = y > b->y1 ? y : b->y1;
}

/* One area query for the box `area`, keeping what the bot's rays may
 * see. */
static void gather(const evo_scene *sc, const evo_bot *b, const box *area,
		   uint16_t mask, shape_set *set)
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
		/* The bounding circle only culls (sample_proximity): sqrt
		 * serves, without hypot's guard against overflow, a third of
		 * the cost at world sizes. */
		if (s->type != EVO_SHAPE_CIRCLE) {
			double ex = s->vx[0] - s->x, ey = s->vy[0] - s->y;
			s->radius = sqrt(ex * ex + ey * ey);
		}
		set->s[kept++] = *s;
	}
	set->n = kept;
}

static void release_set(shape_set *set)
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
static void fan_box(const evo_sensor *se, const frame *f, box *area)
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
 * [0, max], else max. A segment that starts inside sees nothing. */
static double ray_circle(const evo_shape_info *s, double px, double py,
			 double dx, double dy, double max)
{
	double sx = px - s->x, sy = py - s->y;
	double b = sx * sx + sy * sy - s->radius * s->radius;
	double c = sx * dx + sy * dy;
	/* Inside, or outside and heading away: no crossing ahead. */
	if (b < 0 || c > 0)
		return max;
	double rr = dx * dx + dy * dy;
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
		       const double *dx, const double *dy, double *best, int n)
{
	switch (s->type) {
	case EVO_SHAPE_CIRCLE:
		for (int i = 0; i < n; i++)
			best[i] = ray_circle(s, px, py, dx[i], dy[i], best[i]);
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
static void ray_dir(const evo_sensor *se, const frame *f, int i, double *dx,
		    double *dy)
{
	double range = se->def.range;
	*dx = (f->c * se->ray_c[i] - f->s * se->ray_s[i]) * range;
	*dy = (f->s * se->ray_c[i] + f->c * se->ray_s[i]) * range;
}

/* Whether shape s's bounding circle may meet the fan from p whose edge
 * rays are (fx, fy) and (lx, ly): not too far, not behind, not beyond
 * either edge ray. The edge test holds while the fan is convex (spans
 * less than half a turn). */
static int may_meet(const evo_shape_info *s, const evo_sensor_def *d,
		    double px, double py, int convex, double fx, double fy,
		    double lx, double ly)
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
static double sample_proximity(evo_sensor *se, const frame *f,
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
	double best[EVO_PROX_MAX_RAYS];
	int met = 0;
	for (int k = 0; k < set->n; k++) {
		const evo_shape_info *s = &set->s[k];
		if (!may_meet(s, d, px, py, convex, fx, fy, lx, ly))
			continue;
		if (!met) {
			for (int i = 0; i < n; i++) {
				ray_dir(se, f, i, &dx[i], &dy[i]);
				best[i] = 1;
			}
			met = 1;
		}
		rays_shape(s, px, py, dx, dy, best, n);
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

/* ---- bumper and radar -------------------------------------------------- */

/* An angle into (-pi, pi]. */
static double wrap_angle(double a)
{
	a = fmod(a, 2 * M_PI);
	if (a > M_PI)
		a -= 2 * M_PI;
	else if (a <= -M_PI)
		a += 2 * M_PI;
	return a;
}

/* The nearest point of the segment a -> b to p, the parameter clamped to
 * [0, 1] (Kheperax's bumper rule, docs/world.md). */
static void nearest_on_segment(double ax, double ay, double bx, double by,
			       double px, double py, double *qx, double *qy)
{
	double ex = bx - ax, ey = by - ay;
	double ee = ex * ex + ey * ey;
	double t = ee > 0 ? ((px - ax) * ex + (py - ay) * ey) / ee : 0;
	t = t < 0 ? 0 : t > 1 ? 1 : t;
	*qx = ax + t * ex;
	*qy = ay + t * ey;
}

/* The point of shape s nearest to (px, py): on a circle's rim, on a
 * wall, or on a box's outline. */
static void nearest_point(const evo_shape_info *s, double px, double py,
			  double *qx, double *qy)
{
	if (s->type == EVO_SHAPE_CIRCLE) {
		double dx = px - s->x, dy = py - s->y;
		double d = sqrt(dx * dx + dy * dy);
		double k = d > 0 ? s->radius / d : 0;
		*qx = s->x + dx * k;
		*qy = s->y + dy * k;
		return;
	}
	int corners = s->type == EVO_SHAPE_SEGMENT ? 1 : 4;
	double best = INFINITY;
	*qx = s->vx[0];
	*qy = s->vy[0];
	for (int i = 0; i < corners; i++) {
		int j = s->type == EVO_SHAPE_SEGMENT ? 1 : (i + 1) & 3;
		double x, y;
		nearest_on_segment(s->vx[i], s->vy[i], s->vx[j], s->vy[j], px,
				   py, &x, &y);
		double d = (x - px) * (x - px) + (y - py) * (y - py);
		if (d < best) {
			best = d;
			*qx = x;
			*qy = y;
		}
	}
}

/* A bumper: true when the nearest point of some shape it sees lies
 * within reach of the bot's centre, in a direction within arc of the
 * bumper's angle; of the two ends of that arc, the one nearer straight
 * ahead counts and the other does not (Kheperax's rule: its bumpers cover
 * (-90, 0] and [0, 90) degrees). */
static double sample_bumper(const evo_sensor *se, const frame *f,
			    const shape_set *set)
{
	const evo_sensor_def *d = &se->def;
	for (int k = 0; k < set->n; k++) {
		const evo_shape_info *s = &set->s[k];
		if (!(s->category & d->mask))
			continue;
		double qx, qy;
		nearest_point(s, f->x, f->y, &qx, &qy);
		double dx = qx - f->x, dy = qy - f->y;
		if (dx * dx + dy * dy >= d->reach * d->reach)
			continue;
		/* the direction in the bot's frame: + to its right */
		double delta =
		    atan2(-f->s * dx + f->c * dy, f->c * dx + f->s * dy);
		double off = fabs(wrap_angle(delta - d->angle));
		if (off < d->arc ||
		    (off == d->arc && fabs(delta) < fabs(d->angle)))
			return EVO_TRUE;
	}
	return EVO_FALSE;
}

/* A radar: true when the target's bearing from the bot's centre, from
 * its heading, lies in [angle - arc, angle + arc) (one slice of the
 * novelty-search robot's pie). */
static double sample_radar(const evo_scene *sc, int bot,
			   const evo_sensor_def *d, const frame *f)
{
	double tx, ty;
	if (!evo_scene_target_pos(sc, bot, d->target, &tx, &ty))
		return EVO_FALSE;
	double ox = tx - f->x, oy = ty - f->y;
	double a = atan2(-f->s * ox + f->c * oy, f->c * ox + f->s * oy);
	double delta = wrap_angle(a - d->angle);
	return boolean(delta >= -d->arc && delta < d->arc);
}

/* ---- the others ------------------------------------------------------- */

/* Spread of the last positions: the root of the summed variances of x
 * and y. */
static double spread(const evo_bot *b)
{
	int n = b->hist_n < EVO_DOF_HISTORY ? b->hist_n : EVO_DOF_HISTORY;
	if (n < 2)
		return 0;
	/* The positions from the newest back, as two runs of the ring:
	 * hist_i - 1 down to 0, then the end of the ring down. The sums
	 * add in this order, whichever n is. */
	int head = b->hist_i < n ? b->hist_i : n;
	int tail = EVO_DOF_HISTORY - (n - head);
	double mx = 0, my = 0;
	for (int i = b->hist_i - 1; i >= b->hist_i - head; i--) {
		mx += b->hist_x[i];
		my += b->hist_y[i];
	}
	for (int i = EVO_DOF_HISTORY - 1; i >= tail; i--) {
		mx += b->hist_x[i];
		my += b->hist_y[i];
	}
	mx /= n;
	my /= n;
	double v = 0;
	for (int i = b->hist_i - 1; i >= b->hist_i - head; i--) {
		double ex = b->hist_x[i] - mx, ey = b->hist_y[i] - my;
		v += ex * ex + ey * ey;
	}
	for (int i = EVO_DOF_HISTORY - 1; i >= tail; i--) {
		double ex = b->hist_x[i] - mx, ey = b->hist_y[i] - my;
		v += ex * ex + ey * ey;
	}
	return sqrt(v / n);
}

static int holding(const evo_bot *b)
{
	for (int i = 0; i < b->n_actuators; i++)
		if (b->actuator[i].def.kind == EVO_ACTUATOR_CLAW &&
		    b->actuator[i].held >= 0)
			return 1;
	return 0;
}

/* ---- the swarm sensors (sim/scene/swarm.h) --------------------------- */

/* A bot as range-and-bearing sensors hear it: its broadcast actuators'
 * commands, in the order it has them. */
static int peer_2d(void *ctx, int i, evo_swarm_peer *out)
{
	const evo_bot *b = &((const evo_scene *)ctx)->bot[i];
	out->pos[0] = b->x;
	out->pos[1] = b->y;
	out->pos[2] = 0;
	out->n_values = 0;
	int any = 0;
	for (int k = 0; k < b->n_actuators; k++) {
		if (b->actuator[k].def.kind != EVO_ACTUATOR_BROADCAST)
			continue;
		any = 1;
		if (out->n_values < EVO_SWARM_MAX_VALUES)
			out->value[out->n_values++] = b->actuator[k].command;
	}
	return any;
}

/* Where a coloured bot or element is now, for a camera; its reach from
 * there, for occlusion: a cylinder's or box's rim (objects and bots are
 * no obstacles). */
static int where_2d(void *ctx, const evo_blob *bl, double pos[3],
		    double *reach)
{
	const evo_scene *sc = ctx;
	pos[2] = 0;
	*reach = 0;
	if (bl->kind == EVO_BLOB_BOT) {
		if (bl->index < 0 || bl->index >= sc->n_bots)
			return 0;
		pos[0] = sc->bot[bl->index].x;
		pos[1] = sc->bot[bl->index].y;
		return 1;
	}
	if (bl->kind != EVO_BLOB_ELEMENT || bl->index < 0 ||
	    bl->index >= sc->n_elements)
		return 0;
	const evo_element *e = &sc->element[bl->index];
	pos[0] = e->x;
	pos[1] = e->y;
	switch (e->kind) {
	case EVO_ELEM_OBJECT:
		if (!e->active)
			return 0;
		evo_bpose p = sc->be->pose(sc->bw, e->body);
		pos[0] = p.pos[0];
		pos[1] = p.pos[1];
		return 1;
	case EVO_ELEM_ZONE:
		return e->active;
	case EVO_ELEM_CYLINDER:
		*reach = e->size;
		return 1;
	case EVO_ELEM_BOX:
		*reach = hypot(e->half_w, e->half_h);
		return 1;
	}
	return 0;
}

/* A light, ground or range-and-bearing sensor or a camera; obstacles
 * occlude. */
static double sample_swarm(evo_scene *sc, int bot, const evo_sensor_def *d)
{
	const evo_bot *b = &sc->bot[bot];
	evo_swarm_frame f = evo_swarm_frame_2d(b->x, b->y, b->angle);
	evo_swarm_rays rays = {sc->be, sc->bw, EVO_CAT_OBSTACLE, b->body, -1};
	double at[3] = {d->x, d->y, 0};
	if (d->kind == EVO_SENSOR_LIGHT)
		return evo_swarm_light(&sc->swarm, &f, at, d->angle,
				       d->swarm.aperture, &rays);
	if (d->kind == EVO_SENSOR_GROUND)
		return evo_swarm_ground(&sc->swarm, &f, at);
	if (d->kind == EVO_SENSOR_CAMERA)
		return evo_swarm_camera(&sc->swarm, &d->swarm, &f, bot,
					where_2d, sc, &rays);
	return evo_swarm_rab(&d->swarm, &f, bot, sc->n_bots, peer_2d, sc,
			     &rays);
}

/* One sensor's value; set holds the shapes around the bot for a
 * proximity sensor. */
static double sample(evo_scene *sc, int bot, evo_sensor *se, const frame *f,
		     const shape_set *set)
{
	const evo_bot *b = &sc->bot[bot];
	const evo_sensor_def *d = &se->def;
	double px, py, tx, ty;
	switch (d->kind) {
	case EVO_SENSOR_PROXIMITY:
		return sample_proximity(se, f, set);
	case EVO_SENSOR_DISTANCE:
		if (!evo_scene_target_pos(sc, bot, d->target, &tx, &ty))
			return 1;
		to_world(f, d->x, d->y, &px, &py);
		return clamp01(hypot(tx - px, ty - py) / d->scale);
	case EVO_SENSOR_ZONE:
		return boolean(
		    d->target >= 0 && d->target < sc->n_elements &&
		    evo_zone_contains(&sc->element[d->target], f->x, f->y));
	case EVO_SENSOR_BEARING: {
		if (!evo_scene_target_pos(sc, bot, d->target, &tx, &ty))
			return 0.5;
		/* The target in the bot's frame: +y is its right. */
		double ox = tx - f->x, oy = ty - f->y;
		double fwd = f->c * ox + f->s * oy;
		double right = -f->s * ox + f->c * oy;
		double a = atan2(right, fwd);
		if (a <= -M_PI)
			a = M_PI; /* straight behind reads 1, never 0 */
		return clamp01(0.5 + a / (2 * M_PI));
	}
	case EVO_SENSOR_PRESENCE:
		if (d->target >= 0 && d->target < sc->n_elements)
			return boolean(sc->element[d->target].active);
		return boolean(
		    (d->target == EVO_TARGET_NEAREST_OBJECT ||
		     d->target == EVO_TARGET_NEAREST_OPPONENT ||
		     d->target == EVO_TARGET_NEAREST_TEAMMATE) &&
		    evo_scene_target_pos(sc, bot, d->target, &tx, &ty));
	case EVO_SENSOR_OBJECT: {
		to_world(f, d->x, d->y, &px, &py);
		double ux = f->c * cos(d->angle) - f->s * sin(d->angle);
		double uy = f->s * cos(d->angle) + f->c * sin(d->angle);
		return boolean(
		    evo_scene_object_in_reach(sc, px, py, ux, uy, d->reach, d->arc) >= 0);
	}
	case EVO_SENSOR_MOVEMENT:
		return clamp01(spread(b) / d->scale);
	case EVO_SENSOR_RANDOM:
		return evo_rng_unit(&sc->rng);
	case EVO_SENSOR_CONSTANT:
		return clamp01(d->value);
	case EVO_SENSOR_HOLDING:
		return boolean(holding(b));
	case EVO_SENSOR_RADAR:
		return sample_radar(sc, bot, d, f);
	case EVO_SENSOR_BUMPER:
		return sample_bumper(se, f, set);
	case EVO_SENSOR_LIGHT:
	case EVO_SENSOR_GROUND:
	case EVO_SENSOR_RAB:
	case EVO_SENSOR_CAMERA:
		return sample_swarm(sc, bot, d);
	case EVO_SENSOR_KIND_COUNT:
		break;
	}
	return 0;
}

double evo_sensor_sample(evo_scene *sc, int bot, int sensor)
{
	assert(bot >= 0 && bot < sc->n_bots);
	evo_bot *b = &sc->bot[bot];
	assert(sensor >= 0 && sensor < b->n_sensors);
	evo_sensor *se = &b->sensor[sensor];
	frame f = bot_frame(b);
	shape_set set;
	set.s = set.local;
	set.n = 0;
	if (se->def.kind == EVO_SENSOR_PROXIMITY) {
		box area = {INFINITY, INFINITY, -INFINITY, -INFINITY};
		fan_box(se, &f, &area);
		gather(sc, b, &area, se->def.mask, &set);
	} else if (se->def.kind == EVO_SENSOR_BUMPER) {
		double r = se->def.reach;
		box area = {f.x - r, f.y - r, f.x + r, f.y + r};
		gather(sc, b, &area, se->def.mask, &set);
	}
	se->value = sample(sc, bot, se, &f, &set);
	release_set(&set);
	return se->value;
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
static uint16_t bot_area(const evo_bot *b, const frame *f, box *area)
{
	uint16_t mask = 0;
	int n = 0;
	double reach = 0, bump = 0;
	for (int i = 0; i < b->n_sensors; i++) {
		const evo_sensor *se = &b->sensor[i];
		if (se->def.kind == EVO_SENSOR_BUMPER && !se->idle) {
			bump = se->def.reach > bump ? se->def.reach : bump;
			mask |= se->def.mask;
		}
		if (se->def.kind != EVO_SENSOR_PROXIMITY || se->idle)
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
		if (se->def.kind == EVO_SENSOR_PROXIMITY && !se->idle)
			fan_box(se, f, area);
	}
	if (bump > 0) {
		/* bumpers: the square around the bot they reach */
		box_add(area, f->x - bump, f->y - bump);
		box_add(area, f->x + bump, f->y + bump);
	}
	return mask;
}

static void sample_all(evo_scene *sc, int bot, const frame *f,
		       const shape_set *set)
{
	evo_bot *b = &sc->bot[bot];
	for (int i = 0; i < b->n_sensors; i++)
		if (!b->sensor[i].idle)
			b->sensor[i].value =
			    sample(sc, bot, &b->sensor[i], f, set);
}

/* One query serves every proximity sensor: the box that holds all of
 * their fans, for the union of what they see. */
void evo_bot_sense(evo_scene *sc, int bot)
{
	assert(bot >= 0 && bot < sc->n_bots);
	evo_bot *b = &sc->bot[bot];
	frame f = bot_frame(b);
	box area;
	uint16_t mask = bot_area(b, &f, &area);
	shape_set set;
	set.s = set.local;
	set.n = 0;
	if (mask)
		gather(sc, b, &area, mask, &set);
	sample_all(sc, bot, &f, &set);
	release_set(&set);
}

/* ---- every bot: one query per cell ----------------------------------- */

/* Bots are grouped by the cell of this side (metres) that holds the
 * middle of their sensors' box; the bots of a cell share one query of
 * the box that holds all of theirs. In a crowd of a thousand bots a
 * query through Box2D's tree costs more than everything else a bot's
 * sensing does; a cell's query costs a little more than one bot's. */
#define SENSE_CELL 12.0

/* What evo_sense_all keeps for each bot, and for each cell. */
typedef struct sense_bot {
	box area;
	uint16_t mask;
	int cell; /* its cell */
	int next; /* the next bot of its cell, -1 for none */
} sense_bot;

typedef struct sense_cell {
	int64_t key;	  /* where it is */
	int head;	  /* its first bot */
	int first, count; /* its shapes in the shapes buffer */
} sense_cell;

/* A shape's bounds and category, apart from the rest of it: each bot of
 * a cell runs through its cell's shapes, and these few bytes decide. */
typedef struct shape_bounds {
	float x0, y0, x1, y1;
	uint16_t category;
} shape_bounds;

/* The bounds of a shape, a little wider than it (floats, rounded
 * outwards): a shape outside a bot's box cannot meet its rays, the
 * cell's query found it for another bot. */
static shape_bounds bounds_of(const evo_shape_info *s)
{
	double x0, y0, x1, y1;
	if (s->type == EVO_SHAPE_CIRCLE) {
		x0 = s->x - s->radius;
		x1 = s->x + s->radius;
		y0 = s->y - s->radius;
		y1 = s->y + s->radius;
	} else {
		x0 = x1 = s->vx[0];
		y0 = y1 = s->vy[0];
		int corners = s->type == EVO_SHAPE_SEGMENT ? 2 : 4;
		for (int k = 1; k < corners; k++) {
			x0 = s->vx[k] < x0 ? s->vx[k] : x0;
			x1 = s->vx[k] > x1 ? s->vx[k] : x1;
			y0 = s->vy[k] < y0 ? s->vy[k] : y0;
			y1 = s->vy[k] > y1 ? s->vy[k] : y1;
		}
	}
	double pad = 1e-3 * (1 + fabs(x0) + fabs(y0) + fabs(x1) + fabs(y1));
	shape_bounds b = {(float)(x0 - pad), (float)(y0 - pad),
			  (float)(x1 + pad), (float)(y1 + pad), s->category};
	return b;
}

static int overlaps(const shape_bounds *s, const box *a)
{
	return s->x1 >= a->x0 && s->x0 <= a->x1 && s->y1 >= a->y0 &&
	       s->y0 <= a->y1;
}

/* Room for n bots and cells and a hash of 2^bits slots in sc's buffer;
 * NULL when memory runs out. */
static sense_bot *sense_room(evo_scene *sc, int n, int bits, sense_cell **cells,
			     int **slots)
{
	size_t need = (size_t)n * (sizeof(sense_bot) + sizeof(sense_cell)) +
		      ((size_t)1 << bits) * sizeof(int);
	if (need > sc->sense_cap) {
		void *p = realloc(sc->sense_mem, need);
		if (!p)
			return NULL;
		sc->sense_mem = p;
		sc->sense_cap = need;
	}
	sense_bot *sb = sc->sense_mem;
	*cells = (sense_cell *)(sb + n);
	*slots = (int *)(*cells + n);
	return sb;
}

/* Room for m shapes and their bounds; NULL when memory runs out. */
static evo_shape_info *shape_room(evo_scene *sc, size_t m,
				  shape_bounds **bounds)
{
	size_t need = m * (sizeof(evo_shape_info) + sizeof(shape_bounds));
	if (need > sc->sense_shapes_cap) {
		void *p = realloc(sc->sense_shapes, need);
		if (!p)
			return NULL;
		sc->sense_shapes = p;
		sc->sense_shapes_cap = need;
	}
	*bounds = (shape_bounds *)((evo_shape_info *)sc->sense_shapes + m);
	return sc->sense_shapes;
}

/* The cell (SENSE_CELL square) that holds the middle of a box; a box far
 * off (or not a number) is put in a cell of its own, keyed by -1 - bot. */
static int64_t cell_key(const box *a, int bot)
{
	double kx = floor((a->x0 + a->x1) / 2 / SENSE_CELL);
	double ky = floor((a->y0 + a->y1) / 2 / SENSE_CELL);
	if (!(fabs(kx) < 1e9 && fabs(ky) < 1e9))
		return -1 - (int64_t)bot;
	return (int64_t)(ky + 1e9) * 4000000000LL + (int64_t)(kx + 1e9);
}

void evo_sense_all(evo_scene *sc)
{
	int n = sc->n_bots;
	int bits = 4;
	while ((1 << bits) < 2 * n)
		bits++;
	sense_cell *cells;
	int *slots;
	sense_bot *sb = n >= 2 ? sense_room(sc, n, bits, &cells, &slots) : NULL;
	if (!sb) {
		/* one bot (or no memory): its own query, as ever */
		for (int i = 0; i < n; i++)
			evo_bot_sense(sc, i);
		return;
	}
	/* The bots into cells, through a hash of the cells' keys; a cell's
	 * bots are linked in the bots' order. */
	int n_cells = 0, mask_slots = (1 << bits) - 1;
	for (int k = 0; k <= mask_slots; k++)
		slots[k] = -1;
	for (int i = n - 1; i >= 0; i--) {
		/* backwards, pushing on the front: each cell's list ends up in
		 * the bots' order */
		const evo_bot *b = &sc->bot[i];
		frame f = bot_frame(b);
		sense_bot *s = &sb[i];
		s->mask = bot_area(b, &f, &s->area);
		s->cell = -1;
		s->next = -1;
		if (!s->mask)
			continue;
		int64_t key = cell_key(&s->area, i);
		uint64_t h = (uint64_t)key * 0x9E3779B97F4A7C15ull;
		int slot = (int)(h >> (64 - bits));
		while (slots[slot] >= 0 && cells[slots[slot]].key != key)
			slot = (slot + 1) & mask_slots;
		if (slots[slot] < 0) {
			slots[slot] = n_cells;
			cells[n_cells].key = key;
			cells[n_cells].head = -1;
			n_cells++;
		}
		int c = slots[slot];
		s->cell = c;
		s->next = cells[c].head;
		cells[c].head = i;
	}
	/* One query for each cell: the box that holds its bots' boxes. */
	size_t cap = (size_t)n * 16 + QUERY_CAP, used = 0;
	shape_bounds *bounds;
	evo_shape_info *shapes = shape_room(sc, cap, &bounds);
	for (int c = 0; c < n_cells && shapes; c++) {
		box area = {INFINITY, INFINITY, -INFINITY, -INFINITY};
		uint16_t mask = 0;
		for (int i = cells[c].head; i >= 0; i = sb[i].next) {
			box_add(&area, sb[i].area.x0, sb[i].area.y0);
			box_add(&area, sb[i].area.x1, sb[i].area.y1);
			mask |= sb[i].mask;
		}
		int got =
		    evo_scene_query(sc, area.x0, area.y0, area.x1, area.y1,
				    mask, shapes + used, (int)(cap - used));
		if ((size_t)got > cap - used) {
			/* grow and ask again: the bounds are worked out only
			 * after every query, so moving them costs nothing */
			cap = 2 * (used + (size_t)got + QUERY_CAP);
			shapes = shape_room(sc, cap, &bounds);
			if (!shapes)
				break;
			got = evo_scene_query(sc, area.x0, area.y0, area.x1,
					      area.y1, mask, shapes + used,
					      (int)(cap - used));
		}
		cells[c].first = (int)used;
		cells[c].count = got;
		used += (size_t)got;
	}
	if (!shapes) {
		for (int i = 0; i < n; i++)
			evo_bot_sense(sc, i);
		return;
	}
	for (size_t k = 0; k < used; k++)
		bounds[k] = bounds_of(&shapes[k]);
	/* Each bot in order (RANDOM sensors draw in it), with what its own
	 * query would have found: its cell's shapes that overlap its box. */
	for (int i = 0; i < n; i++) {
		evo_bot *b = &sc->bot[i];
		frame f = bot_frame(b);
		shape_set set;
		set.s = set.local;
		set.n = 0;
		const sense_bot *s = &sb[i];
		int first = s->cell >= 0 ? cells[s->cell].first : 0;
		int count = s->cell >= 0 ? cells[s->cell].count : 0;
		const shape_bounds *sbd = bounds + first;
		for (int k = 0; k < count; k++) {
			if (!(sbd[k].category & s->mask) ||
			    !overlaps(&sbd[k], &s->area))
				continue;
			const evo_shape_info *sh = &shapes[first + k];
			if (unseen(sc, b, sh->body))
				continue;
			if (set.n == QUERY_CAP) {
				/* a crowd past the stack's room: this bot
				 * asks on its own */
				set.n = -1;
				break;
			}
			evo_shape_info *d = &set.local[set.n++];
			*d = *sh;
			if (d->type != EVO_SHAPE_CIRCLE) {
				double ex = d->vx[0] - d->x,
				       ey = d->vy[0] - d->y;
				d->radius = sqrt(ex * ex + ey * ey);
			}
		}
		if (set.n < 0) {
			set.n = 0;
			gather(sc, b, &s->area, s->mask, &set);
		}
		sample_all(sc, i, &f, &set);
		release_set(&set);
	}
}
