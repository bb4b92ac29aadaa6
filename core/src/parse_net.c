/* .net: evo's text form of a network (docs/formats.md). Numbers become
 * Q16 with integer arithmetic only, so a file gives the same network on
 * every platform, including one without floating point. */
#include "evo/formats.h"
#include "text.h"

/* Our own copy of the names evo_act_name gives: the parsers must link
 * without net.c. */
#define ACT_NAME(code, name) name,
static const char *const act_names[EVO_ACT_COUNT] = {EVO_ACT_LIST(ACT_NAME)};
#undef ACT_NAME
#define ACT_JOIN(code, name) " " name
#define ACT_ALL		     EVO_ACT_LIST(ACT_JOIN)

#define ID_MAX	 65535u
#define POW10_17 100000000000000000ull

/* A decimal number -?DIGITS(.DIGITS)? to Q16, rounded to nearest with
 * ties away from zero. Returns 0, -1 when malformed, -2 when |value|
 * (after rounding) is not below EVO_NET_WEIGHT_MAX. */
static int parse_q16(evo_txt_slice s, evo_q16 *out)
{
	size_t i = 0, n_int = 0, n_frac = 0;
	uint32_t ip = 0, bits = 0, mag;
	uint64_t frac = 0;
	int neg = 0, k;

	if (i < s.len && s.s[i] == '-') {
		neg = 1;
		i++;
	}
	for (; i < s.len && s.s[i] >= '0' && s.s[i] <= '9'; i++, n_int++)
		if (ip < 1000) /* enough to know it is out of range */
			ip = ip * 10 + (uint32_t)(s.s[i] - '0');
	if (i < s.len && s.s[i] == '.') {
		i++;
		/* Every multiple of 2^-17 has at most 17 decimal places, so
		 * the first 17 digits decide the rounding exactly: with F
		 * those digits as an integer and r < 1 the rest,
		 * floor((F + r) * 2^17 / 10^17) = floor(F / 5^17). */
		for (; i < s.len && s.s[i] >= '0' && s.s[i] <= '9';
		     i++, n_frac++)
			if (n_frac < 17)
				frac = frac * 10 + (uint64_t)(s.s[i] - '0');
		if (n_frac == 0)
			return -1;
	}
	if (i != s.len || n_int == 0)
		return -1;
	for (k = (int)(n_frac < 17 ? n_frac : 17); k < 17; k++)
		frac *= 10;
	/* The first 17 bits of the fraction, by doubling (no division). */
	for (k = 0; k < 17; k++) {
		frac *= 2;
		bits <<= 1;
		if (frac >= POW10_17) {
			frac -= POW10_17;
			bits |= 1;
		}
	}
	if (ip >= EVO_NET_WEIGHT_MAX)
		return -2;
	mag = ip * 65536u + (bits >> 1) + (bits & 1);
	if (mag >= (uint32_t)EVO_NET_WEIGHT_MAX * 65536u)
		return -2;
	*out = neg ? -(evo_q16)mag : (evo_q16)mag;
	return 0;
}

typedef struct net_reader {
	const char *file;
	evo_diag *err;
	evo_netdesc *out;
	uint32_t inputs_line, outputs_line;
	uint32_t n_out_want;
} net_reader;

static int find_node(const evo_netdesc *d, uint32_t id)
{
	int i;
	for (i = 0; i < d->n_nodes; i++)
		if (d->node[i].id == id)
			return i;
	return -1;
}

static evo_status bad_number(net_reader *rd, const evo_txt_entry *e, int r,
			     const char *what, evo_txt_slice num)
{
	if (r == -2)
		evo_txt_diag(
		    rd->err, rd->file, e->line,
		    "expected a %s with |%s| < %u, found '%.*s' in '%.*s'",
		    what, what, (unsigned)EVO_NET_WEIGHT_MAX, EVO_TXT_Q(num),
		    EVO_TXT_Q(e->text));
	else
		evo_txt_diag(rd->err, rd->file, e->line,
			     "expected a decimal number like -1.25 for the %s, "
			     "found '%.*s' in '%.*s'",
			     what, EVO_TXT_Q(num), EVO_TXT_Q(e->text));
	return r == -2 ? EVO_ERR_LIMIT : EVO_ERR_SYNTAX;
}

static evo_status bad_id(net_reader *rd, const evo_txt_entry *e,
			 evo_txt_slice id, const char *form)
{
	evo_txt_diag(rd->err, rd->file, e->line,
		     "expected %s with a node id 0..%u, found '%.*s' in '%.*s'",
		     form, ID_MAX, EVO_TXT_Q(id), EVO_TXT_Q(e->text));
	return EVO_ERR_SYNTAX;
}

/* "inputs:N" or "outputs:M". */
static evo_status read_size(net_reader *rd, const evo_txt_entry *e, int is_in)
{
	const char *kw = is_in ? "inputs" : "outputs";
	uint32_t *line = is_in ? &rd->inputs_line : &rd->outputs_line;
	uint32_t n;
	int r;
	if (*line) {
		evo_txt_diag(rd->err, rd->file, e->line,
			     "expected %s:COUNT once, found it again (first on "
			     "line %u)",
			     kw, (unsigned)*line);
		return EVO_ERR_SYNTAX;
	}
	r = e->n_fields == 2 ? evo_txt_uint(e->field[1], EVO_MAX_SKILL_IO, &n)
			     : -1;
	if (r != 0) {
		evo_txt_diag(
		    rd->err, rd->file, e->line,
		    "expected %s:COUNT with a whole number 0..%u, found "
		    "'%.*s'",
		    kw, (unsigned)EVO_MAX_SKILL_IO, EVO_TXT_Q(e->text));
		return r == -2 ? EVO_ERR_LIMIT : EVO_ERR_SYNTAX;
	}
	*line = e->line;
	if (is_in)
		rd->out->n_in = (uint16_t)n;
	else
		rd->n_out_want = n;
	return EVO_OK;
}

static evo_status read_node(net_reader *rd, const evo_txt_entry *e)
{
	evo_netdesc *d = rd->out;
	evo_netdesc_node *nd;
	uint32_t id;
	unsigned a;
	int i, r;

	if (e->n_fields != 4) {
		evo_txt_diag(rd->err, rd->file, e->line,
			     "expected node:ID:ACTIVATION:BIAS, found '%.*s'",
			     EVO_TXT_Q(e->text));
		return EVO_ERR_SYNTAX;
	}
	if (evo_txt_uint(e->field[1], ID_MAX, &id) != 0)
		return bad_id(rd, e, e->field[1], "node:ID:ACTIVATION:BIAS");
	if (id < d->n_in) {
		evo_txt_diag(
		    rd->err, rd->file, e->line,
		    "expected a node id of at least %u (ids 0..%u are the "
		    "inputs), found '%.*s'",
		    (unsigned)d->n_in, (unsigned)d->n_in - 1,
		    EVO_TXT_Q(e->text));
		return EVO_ERR_NAME;
	}
	i = find_node(d, id);
	if (i >= 0) {
		evo_txt_diag(
		    rd->err, rd->file, e->line,
		    "expected a new node id, found node %u again (first "
		    "on line %u)",
		    (unsigned)id, (unsigned)d->node[i].line);
		return EVO_ERR_NAME;
	}
	if (d->n_nodes >= EVO_NET_MAX_NODES) {
		evo_txt_diag(rd->err, rd->file, e->line,
			     "expected at most %u nodes, found another: '%.*s'",
			     (unsigned)EVO_NET_MAX_NODES, EVO_TXT_Q(e->text));
		return EVO_ERR_LIMIT;
	}
	for (a = 0; a < EVO_ACT_COUNT; a++)
		if (evo_txt_slice_ieq(e->field[2], act_names[a]))
			break;
	if (a == EVO_ACT_COUNT) {
		evo_txt_diag(
		    rd->err, rd->file, e->line,
		    "expected an activation name, found '%.*s'; did you "
		    "mean %s? (known:" ACT_ALL ")",
		    EVO_TXT_Q(e->field[2]),
		    evo_txt_closest(e->field[2], act_names, EVO_ACT_COUNT));
		return EVO_ERR_NAME;
	}
	nd = &d->node[d->n_nodes];
	r = parse_q16(e->field[3], &nd->bias);
	if (r != 0)
		return bad_number(rd, e, r, "bias", e->field[3]);
	nd->id = (uint16_t)id;
	nd->act = (uint8_t)a;
	nd->line = e->line;
	d->n_nodes++;
	return EVO_OK;
}

static evo_status read_output(net_reader *rd, const evo_txt_entry *e)
{
	evo_netdesc *d = rd->out;
	uint32_t id;
	unsigned k;

	if (e->n_fields != 2) {
		evo_txt_diag(rd->err, rd->file, e->line,
			     "expected output:ID, found '%.*s'",
			     EVO_TXT_Q(e->text));
		return EVO_ERR_SYNTAX;
	}
	if (evo_txt_uint(e->field[1], ID_MAX, &id) != 0)
		return bad_id(rd, e, e->field[1], "output:ID");
	if (d->n_out >= rd->n_out_want) {
		evo_txt_diag(rd->err, rd->file, e->line,
			     "expected %u output:ID line%s (outputs:%u), found "
			     "one more: '%.*s'",
			     (unsigned)rd->n_out_want,
			     rd->n_out_want == 1 ? "" : "s",
			     (unsigned)rd->n_out_want, EVO_TXT_Q(e->text));
		return EVO_ERR_COUNT;
	}
	if (find_node(d, id) < 0) {
		evo_txt_diag(
		    rd->err, rd->file, e->line,
		    "expected an output that is a node declared above, "
		    "found %s %u in '%.*s'",
		    id < d->n_in ? "input" : "undeclared node", (unsigned)id,
		    EVO_TXT_Q(e->text));
		return EVO_ERR_NAME;
	}
	for (k = 0; k < d->n_out; k++) {
		if (d->out_id[k] == id) {
			evo_txt_diag(
			    rd->err, rd->file, e->line,
			    "expected each output node once, found node "
			    "%u again (it is output %u)",
			    (unsigned)id, k);
			return EVO_ERR_NAME;
		}
	}
	d->out_id[d->n_out++] = (uint16_t)id;
	return EVO_OK;
}

static evo_status read_link(net_reader *rd, const evo_txt_entry *e)
{
	evo_netdesc *d = rd->out;
	evo_netdesc_link *ln;
	uint32_t from, to, fanin = 0;
	unsigned i;
	int r;

	if (e->n_fields != 4) {
		evo_txt_diag(rd->err, rd->file, e->line,
			     "expected link:FROM:TO:WEIGHT, found '%.*s'",
			     EVO_TXT_Q(e->text));
		return EVO_ERR_SYNTAX;
	}
	if (evo_txt_uint(e->field[1], ID_MAX, &from) != 0)
		return bad_id(rd, e, e->field[1], "link:FROM:TO:WEIGHT");
	if (evo_txt_uint(e->field[2], ID_MAX, &to) != 0)
		return bad_id(rd, e, e->field[2], "link:FROM:TO:WEIGHT");
	if (from >= d->n_in && find_node(d, from) < 0) {
		evo_txt_diag(rd->err, rd->file, e->line,
			     "expected a link from an input or a node declared "
			     "above, found undeclared node %u in '%.*s'",
			     (unsigned)from, EVO_TXT_Q(e->text));
		return EVO_ERR_NAME;
	}
	if (to < d->n_in) {
		evo_txt_diag(
		    rd->err, rd->file, e->line,
		    "expected a link into a node, found a link into input "
		    "%u in '%.*s'",
		    (unsigned)to, EVO_TXT_Q(e->text));
		return EVO_ERR_NAME;
	}
	if (find_node(d, to) < 0) {
		evo_txt_diag(
		    rd->err, rd->file, e->line,
		    "expected a link into a node declared above, found "
		    "undeclared node %u in '%.*s'",
		    (unsigned)to, EVO_TXT_Q(e->text));
		return EVO_ERR_NAME;
	}
	for (i = 0; i < d->n_links; i++) {
		if (d->link[i].to != to)
			continue;
		fanin++;
		if (d->link[i].from == from) {
			evo_txt_diag(
			    rd->err, rd->file, e->line,
			    "expected each link once, found link %u:%u "
			    "again (first on line %u)",
			    (unsigned)from, (unsigned)to,
			    (unsigned)d->link[i].line);
			return EVO_ERR_NAME;
		}
	}
	if (fanin >= EVO_NET_MAX_FANIN) {
		evo_txt_diag(rd->err, rd->file, e->line,
			     "expected at most %u links into node %u, found "
			     "another: '%.*s'",
			     (unsigned)EVO_NET_MAX_FANIN, (unsigned)to,
			     EVO_TXT_Q(e->text));
		return EVO_ERR_LIMIT;
	}
	if (d->n_links >= EVO_NET_MAX_LINKS) {
		evo_txt_diag(rd->err, rd->file, e->line,
			     "expected at most %u links, found another: '%.*s'",
			     (unsigned)EVO_NET_MAX_LINKS, EVO_TXT_Q(e->text));
		return EVO_ERR_LIMIT;
	}
	ln = &d->link[d->n_links];
	r = parse_q16(e->field[3], &ln->weight);
	if (r != 0)
		return bad_number(rd, e, r, "weight", e->field[3]);
	ln->from = (uint16_t)from;
	ln->to = (uint16_t)to;
	ln->line = e->line;
	d->n_links++;
	return EVO_OK;
}

static evo_status read_entry(net_reader *rd, const evo_txt_entry *e)
{
	/* A pointer, not a copy: gcc -Os turns a struct copy into memcpy. */
	const evo_txt_slice *kw = &e->field[0];
	int is_in = evo_txt_slice_ieq(*kw, "inputs");
	if (is_in || evo_txt_slice_ieq(*kw, "outputs")) {
		if (rd->out->n_nodes || rd->out->n_out || rd->out->n_links) {
			evo_txt_diag(
			    rd->err, rd->file, e->line,
			    "expected inputs:COUNT and outputs:COUNT "
			    "before any node, output or link line, found "
			    "'%.*s'",
			    EVO_TXT_Q(e->text));
			return EVO_ERR_SYNTAX;
		}
		return read_size(rd, e, is_in);
	}
	if (!evo_txt_slice_ieq(*kw, "node") &&
	    !evo_txt_slice_ieq(*kw, "output") &&
	    !evo_txt_slice_ieq(*kw, "link")) {
		evo_txt_diag(rd->err, rd->file, e->line,
			     "expected an inputs:, outputs:, node:, output: or "
			     "link: line, found '%.*s'",
			     EVO_TXT_Q(e->text));
		return EVO_ERR_SYNTAX;
	}
	if (!rd->inputs_line || !rd->outputs_line) {
		evo_txt_diag(
		    rd->err, rd->file, e->line,
		    "expected %s before the first node, output or link "
		    "line, found '%.*s'",
		    rd->inputs_line ? "outputs:COUNT" : "inputs:COUNT",
		    EVO_TXT_Q(e->text));
		return EVO_ERR_MISSING;
	}
	if (evo_txt_slice_ieq(*kw, "node"))
		return read_node(rd, e);
	if (evo_txt_slice_ieq(*kw, "output"))
		return read_output(rd, e);
	return read_link(rd, e);
}

evo_status evo_netdesc_parse(const char *buf, size_t len, const char *file,
			     evo_netdesc *out, evo_diag *err)
{
	net_reader rd;
	evo_txt_lexer lx;
	evo_txt_entry e;
	int r;

	out->n_in = out->n_out = out->n_nodes = out->n_links = 0;
	rd.file = file;
	rd.err = err;
	rd.out = out;
	rd.inputs_line = rd.outputs_line = 0;
	rd.n_out_want = 0;
	evo_txt_lex_init(&lx, buf, len, file);
	while ((r = evo_txt_lex_next(&lx, &e, err)) > 0) {
		evo_status st = read_entry(&rd, &e);
		if (st != EVO_OK)
			return st;
	}
	if (r < 0)
		return EVO_ERR_SYNTAX;
	if (!rd.inputs_line || !rd.outputs_line) {
		evo_txt_diag(err, file, evo_txt_lex_end_line(&lx),
			     "expected %s, found the end of the file",
			     rd.inputs_line ? "outputs:COUNT" : "inputs:COUNT");
		return EVO_ERR_MISSING;
	}
	if (out->n_out != rd.n_out_want) {
		evo_txt_diag(
		    err, file, evo_txt_lex_end_line(&lx),
		    "expected %u output:ID line%s (outputs:%u), found %u",
		    (unsigned)rd.n_out_want, rd.n_out_want == 1 ? "" : "s",
		    (unsigned)rd.n_out_want, (unsigned)out->n_out);
		return EVO_ERR_COUNT;
	}
	return EVO_OK;
}
