/* .vardesc: the variables a mind can use (tutorial 3.2). */
#include "evo/formats.h"
#include "text.h"

/* Indexed by evo_var_type. */
static const char *const var_type_names[EVO_VAR_TYPE_COUNT] = {
    "VariableModule",
    "TickWaveSinVariableModule",
    "CounterVariableModule",
};

const char *evo_var_type_name(unsigned type)
{
	return type < EVO_VAR_TYPE_COUNT ? var_type_names[type] : NULL;
}

static evo_status add_var(const evo_txt_entry *e, evo_vardesc *out,
			  const char *file, evo_diag *err)
{
	evo_vardesc_entry *v;
	evo_status st;
	unsigned t;
	uint32_t i;

	if (e->n_fields != 2) {
		evo_txt_diag(
		    err, file, e->line,
		    "expected a variable entry name:type, found '%.*s'",
		    EVO_TXT_Q(e->text));
		return EVO_ERR_SYNTAX;
	}
	if (out->n_vars >= EVO_MAX_VARIABLES) {
		evo_txt_diag(err, file, e->line,
			     "expected at most %u variables, found another: "
			     "'%.*s'",
			     (unsigned)EVO_MAX_VARIABLES, EVO_TXT_Q(e->text));
		return EVO_ERR_LIMIT;
	}
	v = &out->var[out->n_vars];
	st =
	    evo_txt_name(v->name, e->field[0], e, "a variable name", file, err);
	if (st != EVO_OK)
		return st;
	if (e->field[1].len == 0) {
		evo_txt_diag(err, file, e->line,
			     "expected a variable type after ':', found '%.*s'",
			     EVO_TXT_Q(e->text));
		return EVO_ERR_SYNTAX;
	}
	for (t = 0; t < EVO_VAR_TYPE_COUNT; t++)
		if (evo_txt_slice_ieq(e->field[1], var_type_names[t]))
			break;
	if (t == EVO_VAR_TYPE_COUNT) {
		evo_txt_diag(
		    err, file, e->line,
		    "unknown variable type '%.*s', did you mean %s? "
		    "(expected VariableModule, TickWaveSinVariableModule "
		    "or CounterVariableModule)",
		    EVO_TXT_Q(e->field[1]),
		    evo_txt_closest(e->field[1], var_type_names,
				    EVO_VAR_TYPE_COUNT));
		return EVO_ERR_NAME;
	}
	v->type = (uint8_t)t;
	v->line = e->line;
	for (i = 0; i < out->n_vars; i++) {
		if (evo_txt_eq(out->var[i].name, v->name)) {
			evo_txt_diag(err, file, e->line,
				     "expected a new variable name, found '%s' "
				     "again (first on line %u)",
				     v->name, (unsigned)out->var[i].line);
			return EVO_ERR_NAME;
		}
	}
	out->n_vars++;
	return EVO_OK;
}

evo_status evo_vardesc_parse(const char *buf, size_t len, const char *file,
			     evo_vardesc *out, evo_diag *err)
{
	evo_txt_lexer lx;
	evo_txt_entry e;
	int r;

	out->n_vars = 0;
	evo_txt_lex_init(&lx, buf, len, file);
	while ((r = evo_txt_lex_next(&lx, &e, err)) > 0) {
		evo_status st = add_var(&e, out, file, err);
		if (st != EVO_OK)
			return st;
	}
	return r < 0 ? EVO_ERR_SYNTAX : EVO_OK;
}
