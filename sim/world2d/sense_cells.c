/* evo — every bot's sensing in one pass (evo_sense_all, sensors.h): the
 * bots grouped by cells of the world, one area query per cell, and each
 * bot's sensors sampled in the bots' order with the shapes of its cell
 * that its own query would have found. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "world2d/scene_internal.h"
#include "world2d/sensors.h"
#include "world2d/sensors_internal.h"

/* Bots are grouped by the cell of this side (metres) that holds the
 * middle of their sensors' box; the bots of a cell share one query of
 * the box that holds all of theirs. In a crowd of a thousand bots a
 * query through Box2D's tree costs more than everything else a bot's
 * sensing does; a cell's query costs a little more than one bot's. */
#define SENSE_CELL 12.0

/* What evo_sense_all keeps for each bot, and for each cell. */
typedef struct sense_bot {
	sense_box area;
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

static int overlaps(const shape_bounds *s, const sense_box *a)
{
	return s->x1 >= a->x0 && s->x0 <= a->x1 && s->y1 >= a->y0 &&
	       s->y0 <= a->y1;
}

/* A buffer of at least need bytes in *mem (of *cap bytes), kept from one
 * tick to the next; 0 when memory runs out. */
static int room(void **mem, size_t *cap, size_t need)
{
	if (need > *cap) {
		void *p = realloc(*mem, need);
		if (!p)
			return 0;
		*mem = p;
		*cap = need;
	}
	return 1;
}

/* Room for n bots and cells and a hash of 2^bits slots in sc's buffer;
 * NULL when memory runs out. */
static sense_bot *sense_room(evo_scene *sc, int n, int bits, sense_cell **cells,
			     int **slots)
{
	size_t need = (size_t)n * (sizeof(sense_bot) + sizeof(sense_cell)) +
		      ((size_t)1 << bits) * sizeof(int);
	if (!room(&sc->sense_mem, &sc->sense_cap, need))
		return NULL;
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
	if (!room(&sc->sense_shapes, &sc->sense_shapes_cap, need))
		return NULL;
	*bounds = (shape_bounds *)((evo_shape_info *)sc->sense_shapes + m);
	return sc->sense_shapes;
}

/* The cell (SENSE_CELL square) that holds the middle of a box; a box far
 * off (or not a number) is put in a cell of its own, keyed by -1 - bot. */
static int64_t cell_key(const sense_box *a, int bot)
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
		sense_frame f = sense_frame_of(b);
		sense_bot *s = &sb[i];
		s->mask = evo_sense_area(b, &f, &s->area);
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
		sense_box area = {INFINITY, INFINITY, -INFINITY, -INFINITY};
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
		sense_frame f = sense_frame_of(b);
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
			set.local[set.n] = *sh;
			bound_radius(&set.local[set.n++]);
		}
		if (set.n < 0) {
			set.n = 0;
			evo_shapes_gather(sc, b, &s->area, s->mask, &set);
		}
		evo_bot_sense_with(sc, i, &f, &set);
		evo_shapes_release(&set);
	}
}
