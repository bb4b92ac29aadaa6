/* .ades: one skill's description (tutorial chapter 5). The format is a
 * fixed sequence, so the parser walks it entry by entry. */
#include "evo/formats.h"
#include "text.h"

#define MAX_LAYERS 16

/* Indexed by evo_input_type and evo_output_type. */
static const char *const input_names[] = {"SE", "SD", "VA", "VD"};
static const char *const output_names[] = {"MO", "SK", "VA"};
#define N_INPUT_TYPES  (sizeof input_names / sizeof input_names[0])
#define N_OUTPUT_TYPES (sizeof output_names / sizeof output_names[0])

const char *evo_input_type_name(unsigned type)
{
	return type < N_INPUT_TYPES ? input_names[type] : NULL;
}

const char *evo_output_type_name(unsigned type)
{
	return type < N_OUTPUT_TYPES ? output_names[type] : NULL;
}

/* The index of s in names, or -1. */
static int find_type(evo_txt_slice s, const char *const *names, size_t n)
{
	size_t i;
	for (i = 0; i < n; i++)
		if (evo_txt_slice_ieq(s, names[i]))
			return (int)i;
	return -1;
}

/* TYPE:name with a type of either kind: a line of an input or output
 * list, which tells a count mismatch apart from plain garbage. */
static int is_io_line(const evo_txt_entry *e)
{
	return e->n_fields == 2 &&
	       (find_type(e->field[0], input_names, N_INPUT_TYPES) >= 0 ||
		find_type(e->field[0], output_names, N_OUTPUT_TYPES) >= 0);
}

/* Lines that start a later section: meeting one inside a list means the
 * list has fewer lines than its count said. */
static int is_section_start(const evo_txt_entry *e)
{
	if (e->n_fields == 2)
		return evo_txt_slice_ieq(e->field[0], "input") ||
		       evo_txt_slice_ieq(e->field[0], "output") ||
		       evo_txt_slice_ieq(e->field[0], "layers") ||
		       evo_txt_slice_ieq(e->field[0], "class");
	return e->n_fields == 1 && (evo_txt_slice_ieq(e->text, "neural") ||
				    evo_txt_slice_ieq(e->text, "hardCoded"));
}

typedef struct ades_reader {
	evo_txt_lexer lx;
	evo_txt_entry e;
	const char *file;
	evo_diag *err;
	int bad_byte; /* the lexer failed, err is filled */
} ades_reader;

/* 1 with rd->e filled, 0 at the end (or on a bad byte: check bad_byte). */
static int next(ades_reader *rd)
{
	int r = evo_txt_lex_next(&rd->lx, &rd->e, rd->err);
	if (r < 0) {
		rd->bad_byte = 1;
		return 0;
	}
	return r;
}

static evo_status at_end(ades_reader *rd, evo_status st, const char *fmt,
			 unsigned a, unsigned b)
{
	char what[96];
	if (rd->bad_byte)
		return EVO_ERR_SYNTAX;
	evo_txt_fmt(what, sizeof what, fmt, a, b);
	evo_txt_diag(rd->err, rd->file, evo_txt_lex_end_line(&rd->lx),
		     "expected %s, found the end of the file", what);
	return st;
}

/* "input:N" or "output:N". */
static evo_status read_count(ades_reader *rd, const char *kw,
			     uint32_t prev_count, uint32_t *n)
{
	const evo_txt_entry *e = &rd->e;
	int r;
	if (!next(rd))
		return at_end(rd, EVO_ERR_MISSING,
			      kw[0] == 'i' ? "input:COUNT" : "output:COUNT", 0,
			      0);
	if (e->n_fields == 2 && evo_txt_slice_ieq(e->field[0], kw)) {
		r = evo_txt_uint(e->field[1], EVO_MAX_SKILL_IO, n);
		if (r == 0)
			return EVO_OK;
		evo_txt_diag(
		    rd->err, rd->file, e->line,
		    "expected %s:COUNT with a whole number 0..%u, found "
		    "'%.*s'",
		    kw, (unsigned)EVO_MAX_SKILL_IO, EVO_TXT_Q(e->text));
		return r == -2 ? EVO_ERR_LIMIT : EVO_ERR_SYNTAX;
	}
	if (kw[0] == 'o' && is_io_line(e)) {
		evo_txt_diag(
		    rd->err, rd->file, e->line,
		    "expected output:COUNT, found an input line beyond "
		    "the %u that input:%u declares: '%.*s'",
		    (unsigned)prev_count, (unsigned)prev_count,
		    EVO_TXT_Q(e->text));
		return EVO_ERR_COUNT;
	}
	evo_txt_diag(rd->err, rd->file, e->line,
		     "expected %s:COUNT, found '%.*s'", kw, EVO_TXT_Q(e->text));
	return EVO_ERR_SYNTAX;
}

/* n lines TYPE:name into list; *count counts those read, so that on an
 * error it covers only filled entries. */
static evo_status read_io(ades_reader *rd, int outputs, uint32_t n,
			  evo_ades_io *list, uint32_t *count)
{
	const char *const *mine = outputs ? output_names : input_names;
	const char *const *other = outputs ? input_names : output_names;
	size_t n_mine = outputs ? N_OUTPUT_TYPES : N_INPUT_TYPES;
	size_t n_other = outputs ? N_INPUT_TYPES : N_OUTPUT_TYPES;
	const char *kind = outputs ? "output" : "input";
	const char *expect = outputs ? "MO, SK or VA" : "SE, SD, VA or VD";
	const evo_txt_entry *e = &rd->e;
	uint32_t k;

	for (k = 0; k < n; k++) {
		evo_status st;
		int t;
		if (!next(rd))
			return at_end(rd, EVO_ERR_COUNT,
				      outputs ? "an output line TYPE:name "
						"(output %u of %u)"
					      : "an input line TYPE:name "
						"(input %u of %u)",
				      (unsigned)k + 1, (unsigned)n);
		if (is_section_start(e) || e->n_fields != 2) {
			evo_txt_diag(rd->err, rd->file, e->line,
				     "expected an %s line TYPE:name (%s %u of "
				     "%u), found '%.*s'",
				     kind, kind, (unsigned)k + 1, (unsigned)n,
				     EVO_TXT_Q(e->text));
			return is_section_start(e) ? EVO_ERR_COUNT
						   : EVO_ERR_SYNTAX;
		}
		t = find_type(e->field[0], mine, n_mine);
		if (t < 0) {
			int o = find_type(e->field[0], other, n_other);
			evo_txt_diag(rd->err, rd->file, e->line,
				     "expected an %s type (%s), found %s%.*s%s "
				     "in '%.*s'",
				     kind, expect,
				     o < 0     ? "'"
				     : outputs ? "the input type '"
					       : "the output type '",
				     EVO_TXT_Q(e->field[0]), "'",
				     EVO_TXT_Q(e->text));
			return EVO_ERR_NAME;
		}
		st = evo_txt_name(list[k].name, e->field[1], e,
				  outputs ? "an output name" : "an input name",
				  rd->file, rd->err);
		if (st != EVO_OK)
			return st;
		list[k].type = (uint8_t)t;
		list[k].line = e->line;
		*count = k + 1;
	}
	return EVO_OK;
}

/* After the internal function and its parameter nothing may follow. */
static evo_status expect_end(ades_reader *rd, const char *after)
{
	if (!next(rd))
		return rd->bad_byte ? EVO_ERR_SYNTAX : EVO_OK;
	evo_txt_diag(rd->err, rd->file, rd->e.line,
		     "expected the end of the file after %s, found '%.*s'",
		     after, EVO_TXT_Q(rd->e.text));
	return EVO_ERR_SYNTAX;
}

static evo_status read_function(ades_reader *rd, evo_ades *out)
{
	const evo_txt_entry *e = &rd->e;
	evo_status st;
	uint32_t v;
	int r;

	if (!next(rd))
		return at_end(rd, EVO_ERR_MISSING,
			      "the internal function type (neural or "
			      "hardCoded)",
			      0, 0);
	if (is_io_line(e)) {
		evo_txt_diag(
		    rd->err, rd->file, e->line,
		    "expected the internal function type (neural or "
		    "hardCoded), found an output line beyond the %u that "
		    "output:%u declares: '%.*s'",
		    (unsigned)out->n_out, (unsigned)out->n_out,
		    EVO_TXT_Q(e->text));
		return EVO_ERR_COUNT;
	}
	out->kind_line = e->line;
	if (e->n_fields == 1 && evo_txt_slice_ieq(e->text, "neural")) {
		out->kind = EVO_SKILL_NEURAL;
		if (!next(rd))
			return rd->bad_byte ? EVO_ERR_SYNTAX : EVO_OK;
		if (e->n_fields != 2 ||
		    !evo_txt_slice_ieq(e->field[0], "layers")) {
			evo_txt_diag(rd->err, rd->file, e->line,
				     "expected layers:N or the end of the file "
				     "after 'neural', found '%.*s'",
				     EVO_TXT_Q(e->text));
			return EVO_ERR_SYNTAX;
		}
		r = evo_txt_uint(e->field[1], MAX_LAYERS, &v);
		if (r != 0) {
			evo_txt_diag(rd->err, rd->file, e->line,
				     "expected layers:N with a whole number "
				     "0..%u, found '%.*s'",
				     (unsigned)MAX_LAYERS, EVO_TXT_Q(e->text));
			return r == -2 ? EVO_ERR_LIMIT : EVO_ERR_SYNTAX;
		}
		out->layers = v;
		return expect_end(rd, "layers:N");
	}
	if (e->n_fields == 1 && evo_txt_slice_ieq(e->text, "hardCoded")) {
		out->kind = EVO_SKILL_HARDCODED;
		out->layers = 0;
		if (!next(rd))
			return at_end(rd, EVO_ERR_MISSING,
				      "class:NAME after 'hardCoded'", 0, 0);
		if (e->n_fields != 2 ||
		    !evo_txt_slice_ieq(e->field[0], "class")) {
			evo_txt_diag(rd->err, rd->file, e->line,
				     "expected class:NAME after 'hardCoded', "
				     "found '%.*s'",
				     EVO_TXT_Q(e->text));
			return EVO_ERR_MISSING;
		}
		st = evo_txt_name(out->hc_class, e->field[1], e, "a class name",
				  rd->file, rd->err);
		if (st != EVO_OK)
			return st;
		return expect_end(rd, "class:NAME");
	}
	evo_txt_diag(rd->err, rd->file, e->line,
		     "expected the internal function type neural or hardCoded, "
		     "found '%.*s'",
		     EVO_TXT_Q(e->text));
	return EVO_ERR_NAME;
}

evo_status evo_ades_parse(const char *buf, size_t len, const char *file,
			  evo_ades *out, evo_diag *err)
{
	ades_reader rd;
	evo_status st;
	uint32_t n = 0;

	out->name[0] = 0;
	out->hc_class[0] = 0;
	out->n_in = out->n_out = 0;
	out->kind = EVO_SKILL_NEURAL;
	out->layers = 1;
	out->kind_line = out->name_line = 0;
	evo_txt_lex_init(&rd.lx, buf, len, file);
	rd.file = file;
	rd.err = err;
	rd.bad_byte = 0;

	if (!next(&rd))
		return at_end(&rd, EVO_ERR_MISSING, "the skill name", 0, 0);
	if (rd.e.n_fields != 1) {
		evo_txt_diag(err, file, rd.e.line,
			     "expected the skill name first, found '%.*s'",
			     EVO_TXT_Q(rd.e.text));
		return EVO_ERR_MISSING;
	}
	st = evo_txt_name(out->name, rd.e.text, &rd.e, "a skill name", file,
			  err);
	if (st != EVO_OK)
		return st;
	out->name_line = rd.e.line;

	st = read_count(&rd, "input", 0, &n);
	if (st == EVO_OK)
		st = read_io(&rd, 0, n, out->in, &out->n_in);
	if (st == EVO_OK)
		st = read_count(&rd, "output", out->n_in, &n);
	if (st == EVO_OK)
		st = read_io(&rd, 1, n, out->out, &out->n_out);
	if (st == EVO_OK)
		st = read_function(&rd, out);
	return st;
}
