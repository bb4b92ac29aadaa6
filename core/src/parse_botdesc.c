/* .botdesc: the sensors and actuators a mind can use (tutorial 3.1). */
#include "evo/formats.h"
#include "text.h"

enum { BEFORE_SENSORS, IN_SENSORS, IN_ACTUATORS };

/* One sensor or actuator entry, name:type(:params), into list[*n]. */
static evo_status add_entry(const evo_txt_entry *e, evo_botdesc_entry *list,
			    uint32_t *n, uint32_t cap, const char *what,
			    const char *file, evo_diag *err)
{
	evo_botdesc_entry *d;
	evo_txt_slice params;
	evo_status st;
	char label[24];
	uint32_t i;

	if (e->n_fields < 2) {
		evo_txt_diag(err, file, e->line,
			     "expected %s %s entry name:type, found '%.*s'",
			     what[0] == 'a' ? "an" : "a", what,
			     EVO_TXT_Q(e->text));
		return EVO_ERR_SYNTAX;
	}
	if (*n >= cap) {
		evo_txt_diag(err, file, e->line,
			     "expected at most %u %ss, found another: '%.*s'",
			     (unsigned)cap, what, EVO_TXT_Q(e->text));
		return EVO_ERR_LIMIT;
	}
	d = &list[*n];
	evo_txt_fmt(label, sizeof label, "%s %s name",
		    what[0] == 'a' ? "an" : "a", what);
	st = evo_txt_name(d->name, e->field[0], e, label, file, err);
	if (st != EVO_OK)
		return st;
	evo_txt_fmt(label, sizeof label, "%s %s type",
		    what[0] == 'a' ? "an" : "a", what);
	st = evo_txt_name(d->type, e->field[1], e, label, file, err);
	if (st != EVO_OK)
		return st;
	params =
	    e->n_fields > 2 ? evo_txt_rest(e, 2) : evo_txt_rest(e, e->n_fields);
	if (evo_txt_copy(d->params, sizeof d->params, params) != 0) {
		evo_txt_diag(
		    err, file, e->line,
		    "expected %s parameters of at most %u bytes, found "
		    "'%.*s'",
		    what, (unsigned)(EVO_VALUE_MAX - 1), EVO_TXT_Q(params));
		return EVO_ERR_LIMIT;
	}
	d->line = e->line;
	for (i = 0; i < *n; i++) {
		if (evo_txt_eq(list[i].name, d->name)) {
			evo_txt_diag(err, file, e->line,
				     "expected a new %s name, found '%s' again "
				     "(first on line %u)",
				     what, d->name, (unsigned)list[i].line);
			return EVO_ERR_NAME;
		}
	}
	(*n)++;
	return EVO_OK;
}

evo_status evo_botdesc_parse(const char *buf, size_t len, const char *file,
			     evo_botdesc *out, evo_diag *err)
{
	evo_txt_lexer lx;
	evo_txt_entry e;
	int state = BEFORE_SENSORS, r;
	uint32_t sensors_line = 0, actuators_line = 0;

	out->n_sensors = 0;
	out->n_actuators = 0;
	evo_txt_lex_init(&lx, buf, len, file);
	while ((r = evo_txt_lex_next(&lx, &e, err)) > 0) {
		evo_status st;
		/* A keyword is a bare word; "sensors:x" is an entry named
		 * "sensors". */
		int is_sensors =
		    e.n_fields == 1 && evo_txt_slice_ieq(e.text, "SENSORS");
		int is_actuators =
		    e.n_fields == 1 && evo_txt_slice_ieq(e.text, "ACTUATORS");
		if (state == BEFORE_SENSORS) {
			if (!is_sensors) {
				evo_txt_diag(
				    err, file, e.line,
				    "expected the keyword SENSORS first, "
				    "found '%.*s'",
				    EVO_TXT_Q(e.text));
				return is_actuators ? EVO_ERR_MISSING
						    : EVO_ERR_SYNTAX;
			}
			sensors_line = e.line;
			state = IN_SENSORS;
			continue;
		}
		if (is_sensors) {
			evo_txt_diag(
			    err, file, e.line,
			    "expected SENSORS only once, found it again "
			    "(first on line %u)",
			    (unsigned)sensors_line);
			return EVO_ERR_SYNTAX;
		}
		if (is_actuators) {
			if (state == IN_ACTUATORS) {
				evo_txt_diag(
				    err, file, e.line,
				    "expected ACTUATORS only once, found "
				    "it again (first on line %u)",
				    (unsigned)actuators_line);
				return EVO_ERR_SYNTAX;
			}
			actuators_line = e.line;
			state = IN_ACTUATORS;
			continue;
		}
		if (state == IN_SENSORS)
			st = add_entry(&e, out->sensor, &out->n_sensors,
				       EVO_MAX_SENSORS, "sensor", file, err);
		else
			st =
			    add_entry(&e, out->actuator, &out->n_actuators,
				      EVO_MAX_ACTUATORS, "actuator", file, err);
		if (st != EVO_OK)
			return st;
	}
	if (r < 0)
		return EVO_ERR_SYNTAX;
	if (state == BEFORE_SENSORS) {
		evo_txt_diag(
		    err, file, evo_txt_lex_end_line(&lx),
		    "expected the keyword SENSORS, found the end of the "
		    "file");
		return EVO_ERR_MISSING;
	}
	if (state == IN_SENSORS) {
		evo_txt_diag(
		    err, file, evo_txt_lex_end_line(&lx),
		    "expected the keyword ACTUATORS after the sensors, "
		    "found the end of the file");
		return EVO_ERR_MISSING;
	}
	return EVO_OK;
}
