/* Writing a mind image (image.h has the layout). Host-side, but
 * freestanding like the rest of core: it writes into the caller's buffer. */
#include "evo/image.h"
#include "evo/mind.h"
#include "evo/net.h"

static uint32_t align4(uint32_t n)
{
	return (n + 3u) & ~3u;
}

static uint32_t str_size(const char *s)
{
	uint32_t n = 0;
	while (s[n])
		n++;
	return n + 1;
}

static uint32_t names_size(const evo_build *b)
{
	uint32_t n = 0;
	for (unsigned i = 0; i < b->n_sensors; i++)
		n += str_size(b->sensor_name[i]);
	for (unsigned i = 0; i < b->n_actuators; i++)
		n += str_size(b->actuator_name[i]);
	for (unsigned i = 0; i < b->n_vars; i++)
		n += str_size(b->var_name[i]);
	for (unsigned i = 0; i < b->n_skills; i++)
		n += str_size(b->skill[i].name);
	return n;
}

static uint8_t *put_str(uint8_t *p, const char *s)
{
	while (*s)
		*p++ = (uint8_t)*s++;
	*p++ = 0;
	return p;
}

/* Sizes of a network's three arrays in the image. */
static uint32_t net_bytes(const evo_netdesc *d)
{
	return align4(d->n_nodes * (uint32_t)sizeof(evo_net_node)) +
	       align4(d->n_links * (uint32_t)sizeof(evo_net_link)) +
	       align4(d->n_out * (uint32_t)sizeof(uint16_t));
}

evo_status evo_image_write(const evo_build *b, struct evo_net_compile_ws *ws,
			   void *buf, size_t cap, size_t *len)
{
	uint32_t n_io = 0, n_nets = 0, nets_bytes = 0;
	for (unsigned i = 0; i < b->n_skills; i++) {
		const evo_build_skill *k = &b->skill[i];
		n_io += k->n_in + (uint32_t)k->n_out;
		if (k->kind == EVO_SKILL_NEURAL) {
			if (!k->net)
				return EVO_ERR_MISSING;
			n_nets++;
			nets_bytes += net_bytes(k->net);
		}
	}
	if (b->n_skills == 0 || n_io > 0xFFFFu)
		return EVO_ERR_LIMIT;

	evo_image_header h = {0};
	h.magic = EVO_IMAGE_MAGIC;
	h.version = EVO_IMAGE_VERSION;
	h.header_size = sizeof h;
	h.names_hash = evo_names_hash(b->sensor_name, b->n_sensors,
				      b->actuator_name, b->n_actuators,
				      b->var_name, b->n_vars);
	h.n_sensors = b->n_sensors;
	h.n_actuators = b->n_actuators;
	h.n_vars = b->n_vars;
	h.n_skills = b->n_skills;
	h.n_io = (uint16_t)n_io;
	h.n_nets = (uint16_t)n_nets;
	h.off_vars = sizeof h;
	h.off_skills = h.off_vars + align4(b->n_vars);
	h.off_io = h.off_skills + b->n_skills * (uint32_t)sizeof(evo_image_skill);
	h.off_nets = h.off_io + n_io * (uint32_t)sizeof(evo_image_io);
	uint32_t net_data = h.off_nets + n_nets * (uint32_t)sizeof(evo_image_net);
	h.off_names = net_data + nets_bytes;
	h.names_len = names_size(b);
	h.length = h.off_names + align4(h.names_len);
	*len = h.length;
	if (cap < h.length)
		return EVO_ERR_NOMEM;
	if ((uintptr_t)buf % 4)
		return EVO_ERR_ALIGN;

	uint8_t *base = buf;
	for (uint32_t i = 0; i < h.length; i++)
		base[i] = 0;

	uint8_t *var_type = base + h.off_vars;
	for (unsigned i = 0; i < b->n_vars; i++)
		var_type[i] = b->var_type[i];

	evo_image_skill *skill = (evo_image_skill *)(base + h.off_skills);
	evo_image_io *io = (evo_image_io *)(base + h.off_io);
	evo_image_net *net = (evo_image_net *)(base + h.off_nets);
	uint32_t io_pos = 0, net_pos = 0, data = net_data, persist = 0;
	uint16_t hc = 0;
	for (unsigned i = 0; i < b->n_skills; i++) {
		const evo_build_skill *k = &b->skill[i];
		evo_image_skill *out = &skill[i];
		out->in_start = (uint16_t)io_pos;
		out->n_in = k->n_in;
		for (unsigned j = 0; j < k->n_in; j++)
			io[io_pos++] = k->in[j];
		out->out_start = (uint16_t)io_pos;
		out->n_out = k->n_out;
		for (unsigned j = 0; j < k->n_out; j++)
			io[io_pos++] = k->out[j];
		out->kind = k->kind;
		if (k->kind == EVO_SKILL_HARDCODED) {
			out->slot = hc++;
			out->hc_class = evo_name_hash(k->hc_class);
			continue;
		}
		const evo_netdesc *d = k->net;
		evo_image_net *n = &net[net_pos];
		out->slot = (uint16_t)net_pos++;
		n->n_in = d->n_in;
		n->n_out = d->n_out;
		n->n_nodes = (uint16_t)(d->n_in + d->n_nodes);
		n->n_links = d->n_links;
		n->off_nodes = data;
		n->off_links = n->off_nodes +
			       align4(d->n_nodes * (uint32_t)sizeof(evo_net_node));
		n->off_out = n->off_links +
			     align4(d->n_links * (uint32_t)sizeof(evo_net_link));
		data = n->off_out + align4(d->n_out * (uint32_t)sizeof(uint16_t));
		evo_net view;
		evo_status st = evo_net_compile(
			d, ws, (evo_net_node *)(base + n->off_nodes),
			(evo_net_link *)(base + n->off_links),
			(uint16_t *)(base + n->off_out), &view);
		if (st != EVO_OK)
			return st;
		if (evo_net_is_recurrent(&view)) {
			n->persist = persist;
			persist += n->n_nodes;
		} else {
			n->persist = 0xFFFFFFFFu;
		}
	}

	uint8_t *p = base + h.off_names;
	for (unsigned i = 0; i < b->n_sensors; i++)
		p = put_str(p, b->sensor_name[i]);
	for (unsigned i = 0; i < b->n_actuators; i++)
		p = put_str(p, b->actuator_name[i]);
	for (unsigned i = 0; i < b->n_vars; i++)
		p = put_str(p, b->var_name[i]);
	for (unsigned i = 0; i < b->n_skills; i++)
		p = put_str(p, b->skill[i].name);

	*(evo_image_header *)base = h;
	((evo_image_header *)base)->crc = evo_crc32(0, base + 16, h.length - 16);
	return EVO_OK;
}
