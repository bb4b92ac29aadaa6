/* The mind: opening an image, laying out a state, and the tick.
 *
 * docs/mind.md is the reference for the tick and for influence; the
 * comments here say why the code is shaped as it is. */
#include "evo/mind.h"

#include "evo/formats.h"
#include "hardcoded.h"
#include "variables.h"

#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "evo's mind image is little-endian; this target is not"
#endif

/* The image layout is a file format: these sizes are fixed by
 * docs/mind-image.md, on every target. */
_Static_assert(sizeof(evo_image_header) == 56, "image header layout");
_Static_assert(sizeof(evo_image_skill) == 16, "image skill layout");
_Static_assert(sizeof(evo_image_io) == 4, "image io layout");
_Static_assert(sizeof(evo_image_net) == 24, "image net layout");
_Static_assert(sizeof(evo_net_node) == 12, "image node layout");
_Static_assert(sizeof(evo_net_link) == 8, "image link layout");

/* ---- opening an image ------------------------------------------------ */

#define FEED_FORWARD 0xFFFFFFFFu

static int in_image(uint32_t length, uint32_t off, uint32_t count,
		    uint32_t size)
{
	if (off % 4 || off > length)
		return 0;
	return (uint64_t)count * size <= length - off;
}

static evo_status check_io(const evo_mind *m, unsigned skill)
{
	const evo_image_skill *k = &m->skill[skill];
	for (unsigned j = 0; j < k->n_in; j++) {
		const evo_image_io *io = &m->io[k->in_start + j];
		unsigned limit;
		switch (io->type) {
		case EVO_IN_SE:
		case EVO_IN_SD:
			limit = m->n_sensors;
			break;
		case EVO_IN_VA:
		case EVO_IN_VD:
			limit = m->n_vars;
			break;
		default:
			return EVO_ERR_IMAGE_LAYOUT;
		}
		if (io->index >= limit)
			return EVO_ERR_IMAGE_LAYOUT;
	}
	for (unsigned j = 0; j < k->n_out; j++) {
		const evo_image_io *io = &m->io[k->out_start + j];
		switch (io->type) {
		case EVO_OUT_MO:
			if (io->index >= m->n_actuators)
				return EVO_ERR_IMAGE_LAYOUT;
			break;
		case EVO_OUT_SK:
			/* Sub-skills come after their parents: this is what
			 * makes one top-down pass enough, and rules out
			 * cycles in an image. */
			if (io->index <= skill || io->index >= m->n_skills)
				return EVO_ERR_IMAGE_LAYOUT;
			break;
		case EVO_OUT_VA:
			if (io->index >= m->n_vars)
				return EVO_ERR_IMAGE_LAYOUT;
			break;
		default:
			return EVO_ERR_IMAGE_LAYOUT;
		}
	}
	return EVO_OK;
}

/* |v| < EVO_NET_WEIGHT_MAX, the bound on weights and biases that keeps a
 * network's sums from overflowing (docs/fixed-point.md). One unsigned
 * compare: v + lim - 1 lands in [0, 2 lim - 2] exactly when it holds. */
static int weight_in_range(evo_q16 v)
{
	const uint32_t lim = (uint32_t)EVO_NET_WEIGHT_MAX * EVO_Q16_ONE;
	return (uint32_t)v + (lim - 1u) <= 2u * lim - 2u;
}

static evo_status check_net(const evo_mind *m, const evo_image_net *n,
			    uint32_t *persist, uint16_t *max_ff)
{
	uint32_t len = m->length;
	if (n->n_nodes < n->n_in || n->n_nodes - n->n_in > EVO_NET_MAX_NODES ||
	    n->n_links > EVO_NET_MAX_LINKS)
		return EVO_ERR_IMAGE_LAYOUT;
	if (!in_image(len, n->off_nodes, n->n_nodes - n->n_in,
		      sizeof(evo_net_node)) ||
	    !in_image(len, n->off_links, n->n_links, sizeof(evo_net_link)) ||
	    !in_image(len, n->off_out, n->n_out, sizeof(uint16_t)))
		return EVO_ERR_IMAGE_LAYOUT;
	const evo_net_node *nodes =
		(const evo_net_node *)(m->base + n->off_nodes);
	const evo_net_link *links =
		(const evo_net_link *)(m->base + n->off_links);
	const uint16_t *out = (const uint16_t *)(m->base + n->off_out);
	int recurrent = 0;
	for (unsigned i = n->n_in; i < n->n_nodes; i++) {
		const evo_net_node *nd = &nodes[i - n->n_in];
		if (nd->act >= EVO_ACT_COUNT ||
		    nd->link_count > EVO_NET_MAX_FANIN ||
		    (uint32_t)nd->link_start + nd->link_count > n->n_links)
			return EVO_ERR_IMAGE_LAYOUT;
		if (!weight_in_range(nd->bias))
			return EVO_ERR_IMAGE_RANGE;
		for (unsigned l = 0; l < nd->link_count; l++) {
			const evo_net_link *lk = &links[nd->link_start + l];
			if (lk->src >= n->n_nodes)
				return EVO_ERR_IMAGE_LAYOUT;
			if (!weight_in_range(lk->weight))
				return EVO_ERR_IMAGE_RANGE;
			if (lk->src >= i)
				recurrent = 1;
		}
	}
	for (unsigned k = 0; k < n->n_out; k++)
		if (out[k] >= n->n_nodes)
			return EVO_ERR_IMAGE_LAYOUT;
	/* Recurrent networks keep their activations between ticks, so each
	 * gets its own words, allotted in network order; feed-forward ones
	 * share one scratch array. */
	if (recurrent) {
		if (n->persist != *persist)
			return EVO_ERR_IMAGE_LAYOUT;
		*persist += n->n_nodes;
	} else {
		if (n->persist != FEED_FORWARD)
			return EVO_ERR_IMAGE_LAYOUT;
		if (n->n_nodes > *max_ff)
			*max_ff = n->n_nodes;
	}
	return EVO_OK;
}

static evo_status check_skills(evo_mind *m)
{
	uint16_t n_hc = 0, n_neural = 0, max_io = 0;
	for (unsigned i = 0; i < m->n_skills; i++) {
		const evo_image_skill *k = &m->skill[i];
		const evo_image_header *h = (const evo_image_header *)m->base;
		if ((uint32_t)k->in_start + k->n_in > h->n_io ||
		    (uint32_t)k->out_start + k->n_out > h->n_io ||
		    k->n_in > EVO_MAX_SKILL_IO || k->n_out > EVO_MAX_SKILL_IO)
			return EVO_ERR_IMAGE_LAYOUT;
		if (k->n_in > max_io)
			max_io = k->n_in;
		if (k->n_out > max_io)
			max_io = k->n_out;
		evo_status st = check_io(m, i);
		if (st != EVO_OK)
			return st;
		if (k->kind == EVO_SKILL_NEURAL) {
			/* Networks are numbered in tick order, one per neural
			 * skill (recurrent memory is per network). */
			if (k->slot != n_neural++ || k->slot >= m->n_nets)
				return EVO_ERR_IMAGE_LAYOUT;
			const evo_image_net *n = &m->net[k->slot];
			if (n->n_in != k->n_in || n->n_out != k->n_out)
				return EVO_ERR_IMAGE_LAYOUT;
		} else if (k->kind == EVO_SKILL_HARDCODED) {
			int c = evo_hc_index_of(k->hc_class);
			if (c < 0 ||
			    (evo_hc_table[c].n_in >= 0 &&
			     evo_hc_table[c].n_in != k->n_in) ||
			    (evo_hc_table[c].n_out >= 0 &&
			     evo_hc_table[c].n_out != k->n_out))
				return EVO_ERR_IMAGE_CLASS;
			if (k->slot != n_hc)
				return EVO_ERR_IMAGE_LAYOUT;
			n_hc++;
		} else {
			return EVO_ERR_IMAGE_LAYOUT;
		}
	}
	m->n_hardcoded = n_hc;
	m->max_io = max_io;
	return EVO_OK;
}

evo_status evo_mind_open(const void *buf, size_t len, uint32_t names_hash,
			 evo_mind *m)
{
	const uint8_t *base = buf;
	if ((uintptr_t)buf % 4)
		return EVO_ERR_ALIGN;
	if (len < sizeof(evo_image_header))
		return EVO_ERR_IMAGE_LENGTH;
	const evo_image_header *h = buf;
	if (h->magic != EVO_IMAGE_MAGIC)
		return EVO_ERR_IMAGE_MAGIC;
	if (h->version != EVO_IMAGE_VERSION ||
	    h->header_size != sizeof(evo_image_header))
		return EVO_ERR_IMAGE_VERSION;
	if (h->length > len || h->length < sizeof(evo_image_header) ||
	    h->length % 4)
		return EVO_ERR_IMAGE_LENGTH;
	if (evo_crc32(0, base + 16, h->length - 16) != h->crc)
		return EVO_ERR_IMAGE_CRC;
	if (h->names_hash != names_hash)
		return EVO_ERR_IMAGE_NAMES;

	/* Field by field: a struct assignment would call memset, which a
	 * freestanding runtime does not have. */
	m->base = base;
	m->length = h->length;
	m->n_sensors = h->n_sensors;
	m->n_actuators = h->n_actuators;
	m->n_vars = h->n_vars;
	m->n_skills = h->n_skills;
	m->n_nets = h->n_nets;
	if (m->n_skills == 0 || m->n_sensors > EVO_MAX_SENSORS ||
	    m->n_actuators > EVO_MAX_ACTUATORS ||
	    m->n_vars > EVO_MAX_VARIABLES ||
	    !in_image(h->length, h->off_vars, h->n_vars, 1) ||
	    !in_image(h->length, h->off_skills, h->n_skills,
		      sizeof(evo_image_skill)) ||
	    !in_image(h->length, h->off_io, h->n_io, sizeof(evo_image_io)) ||
	    !in_image(h->length, h->off_nets, h->n_nets,
		      sizeof(evo_image_net)) ||
	    !in_image(h->length, h->off_names, h->names_len, 1))
		return EVO_ERR_IMAGE_LAYOUT;
	m->var_type = base + h->off_vars;
	m->skill = (const evo_image_skill *)(base + h->off_skills);
	m->io = (const evo_image_io *)(base + h->off_io);
	m->net = (const evo_image_net *)(base + h->off_nets);
	m->names = (const char *)(base + h->off_names);
	m->names_len = h->names_len;
	if (m->names_len && m->names[m->names_len - 1] != 0)
		return EVO_ERR_IMAGE_LAYOUT;
	for (unsigned i = 0; i < m->n_vars; i++)
		if (m->var_type[i] >= EVO_VAR_TYPE_COUNT)
			return EVO_ERR_IMAGE_LAYOUT;
	uint32_t persist = 0;
	uint16_t max_ff = 0;
	for (unsigned i = 0; i < m->n_nets; i++) {
		evo_status st = check_net(m, &m->net[i], &persist, &max_ff);
		if (st != EVO_OK)
			return st;
	}
	m->n_persist = persist;
	m->max_ff_nodes = max_ff;
	return check_skills(m);
}

void evo_mind_net(const evo_mind *m, unsigned skill, evo_net *net)
{
	const evo_image_net *n = &m->net[m->skill[skill].slot];
	net->n_in = n->n_in;
	net->n_out = n->n_out;
	net->n_nodes = n->n_nodes;
	net->n_links = n->n_links;
	net->nodes = (const evo_net_node *)(m->base + n->off_nodes);
	net->links = (const evo_net_link *)(m->base + n->off_links);
	net->out = (const uint16_t *)(m->base + n->off_out);
}

/* The names table holds sensors, actuators, variables, then skills. */
static const char *nth_name(const evo_mind *m, unsigned n)
{
	uint32_t pos = 0;
	while (n && pos < m->names_len)
		if (m->names[pos++] == 0)
			n--;
	return pos < m->names_len ? m->names + pos : "";
}

const char *evo_mind_sensor_name(const evo_mind *m, unsigned i)
{
	return i < m->n_sensors ? nth_name(m, i) : "";
}

const char *evo_mind_actuator_name(const evo_mind *m, unsigned i)
{
	return i < m->n_actuators ? nth_name(m, m->n_sensors + i) : "";
}

const char *evo_mind_var_name(const evo_mind *m, unsigned i)
{
	return i < m->n_vars ? nth_name(m, m->n_sensors + m->n_actuators + i)
			     : "";
}

const char *evo_mind_skill_name(const evo_mind *m, unsigned i)
{
	return i < m->n_skills ? nth_name(m, m->n_sensors + m->n_actuators +
						     m->n_vars + i)
			       : "";
}

/* ---- the state ------------------------------------------------------- */

/* One layout, used both to size a state and to carve it, so the two
 * cannot disagree. To only count, pass base 0 and a scratch s (integers,
 * not pointer arithmetic on NULL, so that is defined). The 8-byte sums come
 * first and the bytes last, so with mem 8-byte aligned every array is
 * aligned without padding. influence .. hc are the int32 words a reset
 * zeroes, one run of them; hc_class, set once at init, is last. */
static size_t layout(const evo_mind *m, uintptr_t base, evo_state *s)
{
	size_t off = (sizeof(evo_state) + 7u) & ~(size_t)7u;
	unsigned acc = m->n_actuators + m->n_vars;
#define CARVE(field, type, count)                                              \
	do {                                                                   \
		s->field = (type *)(base + off);                               \
		off += sizeof(type) * (size_t)(count);                         \
	} while (0)
	CARVE(acc_num, uint64_t, acc);
	CARVE(influence, evo_q16, m->n_skills);
	CARVE(sensor_prev, evo_q16, m->n_sensors);
	CARVE(persist, evo_q16, m->n_persist);
	CARVE(hc, int32_t, (size_t)m->n_hardcoded * EVO_HC_WORDS);
	CARVE(actuator, evo_q16, m->n_actuators);
	CARVE(var, evo_var_state, m->n_vars);
	CARVE(acc_den, uint32_t, acc);
	CARVE(ff, evo_q16, m->max_ff_nodes);
	CARVE(io_in, evo_q16, m->max_io);
	CARVE(io_out, evo_q16, m->max_io);
	CARVE(hc_class, uint8_t, m->n_hardcoded);
#undef CARVE
	/* A multiple of 8, so that states can sit end to end and
	 * aligned_alloc(8, size) is valid. */
	return (off + 7u) & ~(size_t)7u;
}

size_t evo_state_size(const evo_mind *m)
{
	evo_state scratch;
	return layout(m, 0, &scratch);
}

evo_status evo_state_init(const evo_mind *m, void *mem, size_t size,
			  evo_state **out)
{
	if ((uintptr_t)mem % 8)
		return EVO_ERR_ALIGN;
	if (size < evo_state_size(m))
		return EVO_ERR_NOMEM;
	evo_state *s = mem;
	layout(m, (uintptr_t)mem, s);
	/* Resolve hard-coded classes once, not every tick; evo_mind_open
	 * has checked that each one exists. */
	for (unsigned i = 0; i < m->n_skills; i++) {
		const evo_image_skill *k = &m->skill[i];
		if (k->kind == EVO_SKILL_HARDCODED)
			s->hc_class[k->slot] =
			    (uint8_t)evo_hc_index_of(k->hc_class);
	}
	evo_state_reset(m, s);
	*out = s;
	return EVO_OK;
}

void evo_state_reset(const evo_mind *m, evo_state *s)
{
	s->tick = 0;
	/* influence, sensor_prev, persist and hc: adjacent (layout). */
	for (int32_t *w = s->influence; w < s->actuator; w++)
		*w = 0;
	for (unsigned i = 0; i < m->n_actuators; i++)
		s->actuator[i] = EVO_Q16_HALF;
	for (unsigned i = 0; i < m->n_vars; i++)
		evo_var_reset(m->var_type[i], &s->var[i]);
}

/* ---- the tick -------------------------------------------------------- */

/* A derivative input: 0.5 + delta / 2, delta = now - before. */
static evo_q16 derivative(evo_q16 now, evo_q16 before)
{
	return evo_q16_clamp01(EVO_Q16_HALF + ((now - before + 1) >> 1));
}

/* SE and SD read a sensor, VA and VD a variable; SD and VD (odd types)
 * take the change since the previous tick. */
static void read_inputs(const evo_mind *m, const evo_state *s,
			const evo_image_skill *k, const evo_q16 *sensors)
{
	for (unsigned j = 0; j < k->n_in; j++) {
		const evo_image_io *io = &m->io[k->in_start + j];
		evo_q16 now, before;
		if (io->type <= EVO_IN_SD) {
			now = evo_q16_clamp01(sensors[io->index]);
			/* At tick 0 there is no previous value: no change. */
			before = s->tick ? s->sensor_prev[io->index] : now;
		} else {
			now = s->var[io->index].value;
			before = s->var[io->index].prev;
		}
		s->io_in[j] = io->type & 1u ? derivative(now, before) : now;
	}
}

static void compute(const evo_mind *m, evo_state *s, unsigned i)
{
	const evo_image_skill *k = &m->skill[i];
	if (k->kind == EVO_SKILL_NEURAL) {
		evo_net net;
		evo_mind_net(m, i, &net);
		uint32_t persist = m->net[k->slot].persist;
		evo_q16 *act =
			persist == FEED_FORWARD ? s->ff : s->persist + persist;
		evo_net_eval(&net, act, s->io_in, s->io_out);
	} else {
		evo_hc_ctx c = {
			.in = s->io_in,
			.out = s->io_out,
			.n_in = k->n_in,
			.n_out = k->n_out,
			.mem = s->hc + (unsigned)k->slot * EVO_HC_WORDS,
			.tick = s->tick,
		};
		for (unsigned j = 0; j < k->n_out; j++)
			s->io_out[j] = EVO_Q16_HALF;
		evo_hc_table[s->hc_class[k->slot]].fn(&c);
	}
}

/* MO and VA outputs add influence * value to the weighted mean of their
 * actuator or variable (variables after the actuators in acc_*); SK
 * outputs add to the sub-skill's influence. */
static void write_outputs(const evo_mind *m, evo_state *s, unsigned i,
			  evo_q16 influence)
{
	const evo_image_skill *k = &m->skill[i];
	for (unsigned j = 0; j < k->n_out; j++) {
		const evo_image_io *io = &m->io[k->out_start + j];
		evo_q16 o = evo_q16_clamp01(s->io_out[j]);
		if (io->type == EVO_OUT_SK) {
			evo_q16 *child = &s->influence[io->index];
			evo_q16 sum = *child + evo_q16_mul(influence, o);
			*child = sum > EVO_Q16_ONE ? EVO_Q16_ONE : sum;
		} else {
			unsigned a = io->index;
			if (io->type == EVO_OUT_VA)
				a += m->n_actuators;
			s->acc_num[a] +=
				(uint64_t)(uint32_t)influence * (uint32_t)o;
			s->acc_den[a] += (uint32_t)influence;
		}
	}
}

void evo_mind_step(const evo_mind *m, evo_state *s, const evo_q16 *sensors,
		   evo_q16 *actuators)
{
	unsigned acc = m->n_actuators + m->n_vars;
	for (unsigned a = 0; a < acc; a++) {
		s->acc_num[a] = 0;
		s->acc_den[a] = 0;
	}
	for (unsigned i = 1; i < m->n_skills; i++)
		s->influence[i] = 0;
	s->influence[0] = EVO_Q16_ONE;

	/* Skills run top-down: every parent of skill i has an index below
	 * i, so its influence is final when its turn comes. */
	for (unsigned i = 0; i < m->n_skills; i++) {
		evo_q16 influence = s->influence[i];
		if (influence < EVO_INFLUENCE_MIN)
			continue;
		read_inputs(m, s, &m->skill[i], sensors);
		compute(m, s, i);
		write_outputs(m, s, i, influence);
	}

	/* The influence-weighted means, rounded. Variables change only
	 * here, after every skill has read them, so all readers in a tick
	 * see the same value whatever their order. */
	for (unsigned a = 0; a < acc; a++) {
		uint32_t den = s->acc_den[a];
		evo_q16 w = den ? (evo_q16)evo_u64_div_u32(
					  s->acc_num[a] + den / 2, den)
				: EVO_Q16_HALF;
		if (a < m->n_actuators) {
			s->actuator[a] = w;
			actuators[a] = w;
		} else {
			unsigned v = a - m->n_actuators;
			evo_var_update(m->var_type[v], &s->var[v], den != 0, w);
		}
	}
	for (unsigned i = 0; i < m->n_sensors; i++)
		s->sensor_prev[i] = evo_q16_clamp01(sensors[i]);
	s->tick++;
}
