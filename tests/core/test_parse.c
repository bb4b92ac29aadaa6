/* Tests core/src/parse_*.c on well-formed input: the tutorial's own example
 * files (the mind folder tests/data/minds/T6-NEAT and tests/data/parse/,
 * which also seed the fuzzers), then the
 * lexer's leniencies, then .net numbers. Run from the repository root. */
#include <stdio.h>
#include <string.h>

#include "evo/formats.h"
#include "harness.h"

#define DATA "tests/data/parse/"
/* The tutorial's files that a mind folder holds live in one. */
#define TUTORIAL "tests/data/minds/T6-NEAT/"

static char file_buf[1 << 16];
static size_t file_len;

/* The parsed structs are large, so they are static. */
static evo_botdesc bd;
static evo_vardesc vd;
static evo_ades ad;
static evo_simbatch sb;
static evo_netdesc nd;
static evo_diag err;

static int load(const char *path)
{
	FILE *f = fopen(path, "rb");
	file_len = 0;
	if (!f) {
		TEST_WRITE("cannot open ");
		TEST_WRITE(path);
		TEST_WRITE(" (run from the repository root)\n");
		return 0;
	}
	file_len = fread(file_buf, 1, sizeof file_buf, f);
	fclose(f);
	return 1;
}

#define CHECK_OK(call)                                                         \
	do {                                                                   \
		evo_status st_ = (call);                                       \
		CHECK_EQ_INT(st_, EVO_OK);                                     \
		if (st_ != EVO_OK)                                             \
			CHECK_EQ_STR(err.msg, "(no error)");                   \
	} while (0)

/* Parses a C string with parser fn, as file "t". */
#define PARSE(fn, s, out) fn((s), strlen(s), "t", (out), &err)

TEST(tutorial_botdesc)
{
	CHECK(load(DATA "MyAgentName.botdesc"));
	CHECK_OK(evo_botdesc_parse(file_buf, file_len, "MyAgentName.botdesc",
				   &bd, &err));
	CHECK_EQ_INT(bd.n_sensors, 4);
	CHECK_EQ_INT(bd.n_actuators, 2);
	CHECK_EQ_STR(bd.sensor[0].name, "S1");
	CHECK_EQ_STR(bd.sensor[0].type, "proxSensor");
	CHECK_EQ_STR(bd.sensor[0].params, "");
	CHECK_EQ_INT(bd.sensor[0].line, 3);
	CHECK_EQ_STR(bd.sensor[2].name, "TARG_AZIM");
	CHECK_EQ_STR(bd.sensor[2].type, "TargetSensor");
	CHECK_EQ_STR(bd.sensor[2].params, "1");
	CHECK_EQ_INT(bd.sensor[2].line, 6);
	CHECK_EQ_STR(bd.sensor[3].params, "2");
	/* "ACTUATORS M1:propeller M2:propeller" on one line */
	CHECK_EQ_STR(bd.actuator[0].name, "M1");
	CHECK_EQ_STR(bd.actuator[0].type, "propeller");
	CHECK_EQ_STR(bd.actuator[1].name, "M2");
	CHECK_EQ_INT(bd.actuator[1].line, 9);
}

TEST(botdesc_crlf_bom_blanks)
{
	CHECK(load(DATA "crlf_bom.botdesc"));
	CHECK_OK(evo_botdesc_parse(file_buf, file_len, "crlf_bom.botdesc", &bd,
				   &err));
	CHECK_EQ_INT(bd.n_sensors, 2);
	CHECK_EQ_STR(bd.sensor[0].name, "S1");
	CHECK_EQ_STR(bd.sensor[0].type, "proxSensor");
	CHECK_EQ_INT(bd.sensor[0].line, 3);
	CHECK_EQ_STR(bd.sensor[1].params, "1:extra");
	CHECK_EQ_INT(bd.sensor[1].line, 6);
	CHECK_EQ_INT(bd.n_actuators, 2);
	CHECK_EQ_STR(bd.actuator[1].name, "M2");
	CHECK_EQ_STR(bd.actuator[1].type, "propeller");
}

TEST(botdesc_zero_actuators_and_verbatim_params)
{
	CHECK_OK(PARSE(evo_botdesc_parse, "SENSORS\nCAM:camera: a\nACTUATORS\n",
		       &bd));
	CHECK_EQ_INT(bd.n_sensors, 1);
	CHECK_EQ_INT(bd.n_actuators, 0);
	/* Spaces right after ':' join words into one entry; params keep
	 * what follows the type. */
	CHECK_EQ_STR(bd.sensor[0].params, "a");
	CHECK_EQ_INT(PARSE(evo_botdesc_parse,
			   "SENSORS\nCAM:camera:x: y:z\nACTUATORS", &bd),
		     EVO_OK);
	CHECK_EQ_STR(bd.sensor[0].params, "x: y:z");
	/* Names are case-sensitive: s1 and S1 are two sensors. */
	CHECK_OK(PARSE(evo_botdesc_parse, "SENSORS s1:a S1:a ACTUATORS", &bd));
	CHECK_EQ_INT(bd.n_sensors, 2);
}

TEST(tutorial_vardesc)
{
	CHECK(load(TUTORIAL "T6-NEAT.vardesc"));
	CHECK_OK(evo_vardesc_parse(file_buf, file_len, "MyAgentName.vardesc",
				   &vd, &err));
	CHECK_EQ_INT(vd.n_vars, 3);
	CHECK_EQ_STR(vd.var[0].name, "VAR_SIN");
	CHECK_EQ_INT(vd.var[0].type, EVO_VAR_SINWAVE);
	CHECK_EQ_STR(vd.var[1].name, "VAR_BASE");
	CHECK_EQ_INT(vd.var[1].type, EVO_VAR_PLAIN);
	CHECK_EQ_INT(vd.var[1].line, 3);
	CHECK_EQ_STR(vd.var[2].name, "VAR_COUNT");
	CHECK_EQ_INT(vd.var[2].type, EVO_VAR_COUNTER);
	CHECK_EQ_INT(vd.var[2].line, 7);
}

TEST(vardesc_empty_and_case)
{
	CHECK_OK(evo_vardesc_parse("", 0, "e", &vd, &err));
	CHECK_EQ_INT(vd.n_vars, 0);
	CHECK_OK(evo_vardesc_parse(NULL, 0, "e", &vd, &err));
	CHECK_OK(PARSE(evo_vardesc_parse, "# only a comment\n\n   \n", &vd));
	CHECK_EQ_INT(vd.n_vars, 0);
	CHECK_OK(PARSE(evo_vardesc_parse,
		       "a:countervariablemodule\tb : VARIABLEMODULE", &vd));
	CHECK_EQ_INT(vd.n_vars, 2);
	CHECK_EQ_INT(vd.var[0].type, EVO_VAR_COUNTER);
	CHECK_EQ_INT(vd.var[1].type, EVO_VAR_PLAIN);
	CHECK_EQ_STR(evo_var_type_name(EVO_VAR_SINWAVE),
		     "TickWaveSinVariableModule");
	CHECK(evo_var_type_name(EVO_VAR_TYPE_COUNT) == NULL);
}

TEST(tutorial_collect)
{
	CHECK(load(TUTORIAL "Skills/Collect/Collect.ades"));
	CHECK_OK(evo_ades_parse(file_buf, file_len, "Collect.ades", &ad, &err));
	CHECK_EQ_STR(ad.name, "Collect");
	CHECK_EQ_INT(ad.name_line, 1);
	CHECK_EQ_INT(ad.n_in, 2);
	CHECK_EQ_INT(ad.in[0].type, EVO_IN_SE);
	CHECK_EQ_STR(ad.in[0].name, "SENSOBJ");
	CHECK_EQ_INT(ad.in[1].line, 4);
	CHECK_EQ_INT(ad.n_out, 3);
	CHECK_EQ_INT(ad.out[0].type, EVO_OUT_SK);
	CHECK_EQ_STR(ad.out[0].name, "GTO+Avoid");
	CHECK_EQ_STR(ad.out[1].name, "GTDZ+Avoid");
	CHECK_EQ_STR(ad.out[2].name, "ClawControl");
	CHECK_EQ_INT(ad.out[2].line, 8);
	CHECK_EQ_INT(ad.kind, EVO_SKILL_NEURAL);
	CHECK_EQ_INT(ad.kind_line, 9);
	CHECK_EQ_INT(ad.layers, 2);
}

TEST(tutorial_move_forward)
{
	CHECK(load(TUTORIAL "Skills/moveForward/moveForward.ades"));
	CHECK_OK(
	    evo_ades_parse(file_buf, file_len, "moveForward.ades", &ad, &err));
	CHECK_EQ_STR(ad.name, "moveForward");
	CHECK_EQ_INT(ad.n_in, 0);
	CHECK_EQ_INT(ad.n_out, 2);
	CHECK_EQ_INT(ad.out[0].type, EVO_OUT_MO);
	CHECK_EQ_STR(ad.out[1].name, "MotR");
	CHECK_EQ_INT(ad.kind, EVO_SKILL_HARDCODED);
	CHECK_EQ_STR(ad.hc_class, "MoveForward");
	CHECK_EQ_INT(ad.kind_line, 6);
}

TEST(tutorial_avoid)
{
	CHECK(load(TUTORIAL "Skills/Avoid/Avoid.ades"));
	CHECK_OK(evo_ades_parse(file_buf, file_len, "Avoid.ades", &ad, &err));
	CHECK_EQ_INT(ad.n_in, 15);
	CHECK_EQ_INT(ad.in[10].type, EVO_IN_SD);
	CHECK_EQ_STR(ad.in[10].name, "US_10");
	/* "VA: VAR_SIN": the space after ':' is allowed */
	CHECK_EQ_INT(ad.in[13].type, EVO_IN_VA);
	CHECK_EQ_STR(ad.in[13].name, "VAR_SIN");
	CHECK_EQ_INT(ad.in[13].line, 16);
	CHECK_EQ_INT(ad.n_out, 4);
	CHECK_EQ_STR(ad.out[3].name, "moveBackwards");
	CHECK_EQ_INT(ad.layers, 2);
	CHECK_EQ_INT(ad.kind_line, 23);
}

TEST(ades_crlf_bom_case_one_line)
{
	CHECK(load(DATA "crlf_bom.ades"));
	CHECK_OK(
	    evo_ades_parse(file_buf, file_len, "crlf_bom.ades", &ad, &err));
	CHECK_EQ_STR(ad.name, "Collect");
	CHECK_EQ_INT(ad.n_in, 1);
	CHECK_EQ_INT(ad.in[0].type, EVO_IN_SE);
	CHECK_EQ_INT(ad.n_out, 2);
	CHECK_EQ_STR(ad.out[1].name, "GTDZ+Avoid");
	CHECK_EQ_INT(ad.out[1].line, 6);
	CHECK_EQ_INT(ad.layers, 0);
	/* neural without layers: one hidden layer; whole skill on a line */
	CHECK_OK(
	    PARSE(evo_ades_parse, "S input:1 VD:v output:1 VA:v neural", &ad));
	CHECK_EQ_INT(ad.layers, 1);
	CHECK_EQ_INT(ad.in[0].type, EVO_IN_VD);
	CHECK_EQ_INT(ad.out[0].type, EVO_OUT_VA);
	CHECK_EQ_STR(evo_input_type_name(EVO_IN_SD), "SD");
	CHECK_EQ_STR(evo_output_type_name(EVO_OUT_SK), "SK");
	CHECK(evo_output_type_name(3) == NULL);
	CHECK(evo_input_type_name(4) == NULL);
}

TEST(tutorial_simbatch)
{
	CHECK(load(TUTORIAL "Tasks/T6-NEAT.simbatch"));
	CHECK_OK(evo_simbatch_parse(file_buf, file_len, "T6-NEAT.simbatch", &sb,
				    &err));
	CHECK_EQ_INT(sb.n_pairs, 11);
	CHECK_EQ_INT(sb.n_warnings, 0);
	CHECK_EQ_STR(evo_simbatch_get(&sb, "TYPE"), "LEARNSIM");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "BOTMODEL"), "BotType6");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "BOTNAME"), "T6-NEAT");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "MASTERSKILL"), "Avoid");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "LEARNINGSKILL"), "Avoid");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "ENV"), "EXP_Avoid");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "LEARNINGMETHOD"), "NEAT");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "ROOTFOLDER"), "Minds/T6-NEAT");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "NUMGEN"), "50");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "EVALREP"), "3");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "ticklim"), "100000");
	CHECK(evo_simbatch_get(&sb, "SEED") == NULL);
	CHECK_EQ_INT(sb.pair[6].line, 9);
	CHECK_EQ_INT(sb.pair[7].line, 9);
	CHECK_EQ_INT(sb.pair[10].line, 11);
}

TEST(simbatch_mixed)
{
	CHECK(load(DATA "mixed.simbatch"));
	CHECK_OK(evo_simbatch_parse(file_buf, file_len, "mixed.simbatch", &sb,
				    &err));
	/* TYPE's value is kept as written; keys are stored upper-cased. */
	CHECK_EQ_STR(evo_simbatch_get(&sb, "TYPE"), "demosim");
	CHECK_EQ_STR(sb.pair[2].key, "SEED");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "SEED"), "0");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "THREADS"), "4");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "ROOTFOLDER"), "C:/Minds/T6");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "NEAT_C1"), "1.0");
	CHECK(evo_simbatch_get(&sb, "NUMGENS") == NULL);
	CHECK(evo_simbatch_get(&sb, "NUMGEN") == NULL);
	CHECK_EQ_INT(sb.n_warnings, 1);
	CHECK_EQ_STR(sb.warning[0].msg,
		     "mixed.simbatch:3: unknown key 'NUMGENS' ignored; did you "
		     "mean NUMGEN?");
}

TEST(simbatch_many_warnings)
{
	static char text[2048];
	size_t n = 0;
	int i;
	for (i = 0; i < 20; i++) {
		memcpy(text + n, "XYZ:1\n", 6);
		n += 6;
	}
	CHECK_OK(evo_simbatch_parse(text, n, "w", &sb, &err));
	CHECK_EQ_INT(sb.n_warnings, 20);
	CHECK_EQ_INT(sb.n_pairs, 0);
	CHECK_CONTAINS(sb.warning[EVO_MAX_WARNINGS - 1].msg, "w:16: ");
}

/* A learning method's keys are all kept, upper-cased, for the method to
 * check; a bare prefix is an unknown key like any other. */
TEST(simbatch_method_keys_are_kept)
{
	static const char text[] = "neat_popsize:24\nGA_Whatever:1\n"
				   "SA_T0:5\nNEAT_:3\nNEATPOP:1\n";
	CHECK_OK(evo_simbatch_parse(text, sizeof text - 1, "m", &sb, &err));
	CHECK_EQ_INT(sb.n_pairs, 3);
	CHECK_EQ_STR(evo_simbatch_get(&sb, "NEAT_POPSIZE"), "24");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "GA_WHATEVER"), "1");
	CHECK_EQ_STR(evo_simbatch_get(&sb, "SA_T0"), "5");
	CHECK_EQ_INT(sb.n_warnings, 2);
	CHECK_CONTAINS(sb.warning[0].msg, "m:4: unknown key 'NEAT_'");
}

/* TEAM is the one key given once per team; the pairs keep every one, in
 * order, with its line; any other key twice is still an error. */
TEST(simbatch_team_lines_repeat)
{
	static const char text[] =
	    "TYPE:DEMO2DSIMMULTI\n"
	    "team:Red:Forager:BotType8:4:Forage\n"
	    "ENV:EXP_Forage TEAM:Blue:Forager:BotType8:2:Forage\n"
	    "ALTERNATE:3\n";
	CHECK_OK(evo_simbatch_parse(text, sizeof text - 1, "t", &sb, &err));
	CHECK_EQ_INT(sb.n_pairs, 5);
	CHECK_EQ_STR(evo_simbatch_get(&sb, "TEAM"),
		     "Red:Forager:BotType8:4:Forage");
	CHECK_EQ_STR(sb.pair[1].key, "TEAM");
	CHECK_EQ_STR(sb.pair[3].key, "TEAM");
	CHECK_EQ_STR(sb.pair[3].value, "Blue:Forager:BotType8:2:Forage");
	CHECK_EQ_INT(sb.pair[3].line, 3);
	CHECK_EQ_STR(evo_simbatch_get(&sb, "ALTERNATE"), "3");
	static const char twice[] = "TEAM:a:b:c:1:d\nLEARNINGTEAM:a\n"
				    "LEARNINGTEAM:b\n";
	CHECK(evo_simbatch_parse(twice, sizeof twice - 1, "t", &sb, &err) ==
	      EVO_ERR_NAME);
	CHECK_CONTAINS(err.msg, "t:3: expected each key once, found "
				"LEARNINGTEAM again (first on line 2)");
	static const char zero[] = "ALTERNATE:0\n";
	CHECK(evo_simbatch_parse(zero, sizeof zero - 1, "t", &sb, &err) ==
	      EVO_ERR_SYNTAX);
	CHECK_CONTAINS(err.msg, "ALTERNATE: expected a whole number from 1 to "
				"1000000, found '0'");
}

TEST(simbatch_tables)
{
	size_t i, n = 0;
	for (i = 0; evo_simbatch_key_defs[i].name; i++)
		n++;
	/* the tutorial's 12, THREADS, HIDDEN, TARGETFITNESS, the five
	 * remote keys (LCMURL, REMOTENAME, REMOTETIMEOUT, LCMKEYFILE,
	 * CANURL) and the five of teams (TEAM, LEARNINGTEAM, TEAMGENOME,
	 * TEAMFITNESS, ALTERNATE) and the three of LEARNSIMCONTINUOUS
	 * (SKILLORDER, ROUNDS, VALIDATION), and the Lua limits (LUABUDGET,
	 * LUAMEMORY), and the double pole's POLEPROTOCOL */
	CHECK_EQ_INT(n, 32);
	CHECK(n <= EVO_MAX_SIMBATCH);
	n = 0;
	for (i = 0; evo_task_types[i]; i++)
		n++;
	/* DEMO3DSIMMULTI and LEARN3DSIMMULTI (docs/teams.md) made 11 13 */
	CHECK_EQ_INT(n, 13);
	CHECK(evo_simbatch_get(NULL, "TYPE") == NULL);
}

/* Parses "TYPE:DEMOSIM\nLINE\n": its status, err filled. */
static evo_status simbatch_line(const char *line)
{
	char text[400];
	int n = snprintf(text, sizeof text, "TYPE:DEMOSIM\n%s\n", line);
	return evo_simbatch_parse(text, (size_t)n, "t.simbatch", &sb, &err);
}

/* Every whole-number key takes its bounds and refuses one past them, at
 * its line, naming itself and its range; the table's names are distinct
 * upper-case keys that fit a pair. */
TEST(simbatch_every_whole_key_is_checked_at_its_bounds)
{
	int wholes = 0;
	for (const evo_simbatch_key_def *d = evo_simbatch_key_defs; d->name;
	     d++) {
		CHECK(strlen(d->name) < EVO_NAME_MAX);
		for (const char *c = d->name; *c; c++)
			CHECK((*c >= 'A' && *c <= 'Z') || *c == '_');
		for (const evo_simbatch_key_def *e = d + 1; e->name; e++)
			CHECK(strcmp(d->name, e->name) != 0);
		CHECK(evo_simbatch_key_find(d->name) == d);
		if (d->kind != EVO_KEY_WHOLE)
			continue;
		wholes++;
		char line[128], want[300], range[200];
		evo_simbatch_key_range(d, range, sizeof range);
		snprintf(line, sizeof line, "%s:%lld", d->name,
			 (long long)d->lo);
		CHECK_OK(simbatch_line(line));
		snprintf(line, sizeof line, "%s:%lld", d->name,
			 (long long)d->hi);
		CHECK_OK(simbatch_line(line));
		snprintf(line, sizeof line, "%s:%lld", d->name,
			 (long long)d->hi + 1);
		CHECK(simbatch_line(line) == EVO_ERR_LIMIT);
		snprintf(want, sizeof want,
			 "t.simbatch:2: %s: expected %s, found '%lld'", d->name,
			 range, (long long)d->hi + 1);
		CHECK_EQ_STR(err.msg, want);
		if (d->lo > 0) {
			snprintf(line, sizeof line, "%s:%lld", d->name,
				 (long long)d->lo - 1);
			CHECK(simbatch_line(line) == EVO_ERR_SYNTAX);
			CHECK_CONTAINS(err.msg, "t.simbatch:2: ");
		}
	}
	/* NUMGEN, EVALREP, TICKLIM, POPSIZE, SEED, THREADS, HIDDEN,
	 * ALTERNATE, ROUNDS, VALIDATION, LUABUDGET, LUAMEMORY */
	CHECK_EQ_INT(wholes, 12);
	CHECK(evo_simbatch_key_find("numgen") != NULL);
	CHECK(evo_simbatch_key_find("NEAT_C1") == NULL);
}

#define A10 "aaaaaaaaaa"
#define A63 A10 A10 A10 A10 A10 A10 "aaa"

/* The values and each kind of key, with the ranges worked out
 * by hand: a population of 10,000, 1,024 threads, a hidden layer of 256
 * nodes, a timeout above 0 and at most an hour, a name of 63
 * characters. */
TEST(simbatch_ranges_of_each_kind)
{
	CHECK(simbatch_line("HIDDEN:2147483647") == EVO_ERR_LIMIT);
	CHECK_EQ_STR(err.msg, "t.simbatch:2: HIDDEN: expected a whole number "
			      "from 1 to 256, found '2147483647'");
	CHECK(simbatch_line("THREADS:2147483647") == EVO_ERR_LIMIT);
	CHECK_EQ_STR(err.msg, "t.simbatch:2: THREADS: expected a whole number "
			      "from 1 to 1024, found '2147483647'");
	CHECK(simbatch_line("POPSIZE:99999999999") == EVO_ERR_LIMIT);
	CHECK_CONTAINS(err.msg, "POPSIZE: expected a whole number from 1 to "
				"10000");
	CHECK_OK(simbatch_line("THREADS:1024"));
	CHECK_OK(simbatch_line("HIDDEN:256"));
	CHECK_OK(simbatch_line("POPSIZE:10000"));
	/* a number */
	CHECK_OK(simbatch_line("REMOTETIMEOUT:3600"));
	CHECK_OK(simbatch_line("REMOTETIMEOUT:3600.000000"));
	CHECK_OK(simbatch_line("REMOTETIMEOUT:0.000001"));
	CHECK_OK(simbatch_line("REMOTETIMEOUT:.5"));
	CHECK(simbatch_line("REMOTETIMEOUT:3600.000001") == EVO_ERR_LIMIT);
	CHECK_EQ_STR(err.msg, "t.simbatch:2: REMOTETIMEOUT: expected a number "
			      "above 0 and at most 3600, found '3600.000001'");
	CHECK(simbatch_line("REMOTETIMEOUT:0") == EVO_ERR_LIMIT);
	CHECK(simbatch_line("REMOTETIMEOUT:-1") == EVO_ERR_LIMIT);
	CHECK(simbatch_line("REMOTETIMEOUT:soon") == EVO_ERR_SYNTAX);
	CHECK(simbatch_line("REMOTETIMEOUT:1e3") == EVO_ERR_SYNTAX);
	CHECK(simbatch_line("REMOTETIMEOUT:0.0000001") == EVO_ERR_SYNTAX);
	CHECK(simbatch_line("REMOTETIMEOUT:1.") == EVO_OK);
	CHECK(simbatch_line("REMOTETIMEOUT:.") == EVO_ERR_SYNTAX);
	CHECK(simbatch_line("REMOTETIMEOUT:99999999999999999999") ==
	      EVO_ERR_LIMIT);
	CHECK_OK(simbatch_line("TARGETFITNESS:-15.5"));
	CHECK_OK(simbatch_line("TARGETFITNESS:1000000000000"));
	CHECK(simbatch_line("TARGETFITNESS:1000000000000.5") == EVO_ERR_LIMIT);
	CHECK(simbatch_line("TARGETFITNESS:inf") == EVO_ERR_SYNTAX);
	/* a name */
	CHECK_OK(simbatch_line("REMOTENAME:sim-1_A"));
	/* 63 characters, then 64 */
	CHECK_OK(simbatch_line("REMOTENAME:" A63));
	CHECK(simbatch_line("REMOTENAME:" A63 "a") == EVO_ERR_SYNTAX);
	CHECK(simbatch_line("REMOTENAME:a/b") == EVO_ERR_SYNTAX);
	CHECK_EQ_STR(err.msg, "t.simbatch:2: REMOTENAME: expected names of 1 "
			      "to 63 letters, digits, '_' or '-', joined by "
			      "',', found 'a/b'");
	/* several names, each in range; none empty */
	CHECK_OK(simbatch_line("REMOTENAME:sim1,sim2"));
	CHECK_OK(simbatch_line("REMOTENAME:a," A63));
	CHECK(simbatch_line("REMOTENAME:a," A63 "a") == EVO_ERR_SYNTAX);
	CHECK(simbatch_line("REMOTENAME:sim1,") == EVO_ERR_SYNTAX);
	CHECK(simbatch_line("REMOTENAME:,sim1") == EVO_ERR_SYNTAX);
	CHECK(simbatch_line("REMOTENAME:sim1,,sim2") == EVO_ERR_SYNTAX);
	CHECK(simbatch_line("REMOTENAME:sim1, sim2") == EVO_ERR_SYNTAX);
	/* a word, any case */
	CHECK_OK(simbatch_line("LEARNINGMETHOD:genetic"));
	CHECK(simbatch_line("LEARNINGMETHOD:NEET") == EVO_ERR_NAME);
	CHECK_EQ_STR(err.msg, "t.simbatch:2: LEARNINGMETHOD: expected NEAT, "
			      "GENETIC, ANNEALING, CMAES, NOVELTY or MAPELITES, "
			      "found 'NEET'; did you "
			      "mean NEAT?");
	/* a method's key is the method's to check */
	CHECK_OK(simbatch_line("NEAT_POPSIZE:99999999999"));
	/* the public check says what the parser does */
	const evo_simbatch_key_def *t = evo_simbatch_key_find("REMOTETIMEOUT");
	CHECK(t && evo_simbatch_key_ok(t, "2") && !evo_simbatch_key_ok(t, "0"));
}

TEST(net_file)
{
	CHECK(load(DATA "xor.net"));
	CHECK_OK(evo_netdesc_parse(file_buf, file_len, "xor.net", &nd, &err));
	CHECK_EQ_INT(nd.n_in, 2);
	CHECK_EQ_INT(nd.n_out, 1);
	CHECK_EQ_INT(nd.out_id[0], 3);
	CHECK_EQ_INT(nd.n_nodes, 2);
	CHECK_EQ_INT(nd.node[0].id, 2);
	CHECK_EQ_INT(nd.node[0].act, EVO_ACT_TANH);
	CHECK_EQ_INT(nd.node[0].bias, 32768);
	CHECK_EQ_INT(nd.node[0].line, 4);
	CHECK_EQ_INT(nd.node[1].act, EVO_ACT_NEAT_SIGMOID);
	CHECK_EQ_INT(nd.node[1].bias, -81920);
	CHECK_EQ_INT(nd.n_links, 5);
	CHECK_EQ_INT(nd.link[0].from, 0);
	CHECK_EQ_INT(nd.link[0].to, 2);
	CHECK_EQ_INT(nd.link[0].weight, 65536);
	/* 0.53 * 65536 = 34734.08 */
	CHECK_EQ_INT(nd.link[1].weight, -34734);
	CHECK_EQ_INT(nd.link[2].weight, 8355840);
	/* self-loop (recurrent) allowed; just under half an ulp: 0 */
	CHECK_EQ_INT(nd.link[3].from, 3);
	CHECK_EQ_INT(nd.link[3].weight, 0);
	/* exactly half an ulp (2^-17) rounds away from zero */
	CHECK_EQ_INT(nd.link[4].weight, 1);
	CHECK_EQ_INT(nd.link[4].line, 11);
}

/* The Q16 value of "link:0:1:<num>" in a one-node network. */
static long long q16_of(const char *num, evo_status *st)
{
	static char text[512];
	size_t n = 0, i;
	const char *head = "inputs:1 outputs:1 node:1:identity:0 output:1 "
			   "link:0:1:";
	for (i = 0; head[i]; i++)
		text[n++] = head[i];
	for (i = 0; num[i] && n < sizeof text - 1; i++)
		text[n++] = num[i];
	*st = evo_netdesc_parse(text, n, "q", &nd, &err);
	return *st == EVO_OK ? nd.link[0].weight : -999999999;
}

TEST(net_numbers_round_exactly)
{
	static const struct {
		const char *text;
		long long q16;
	} cases[] = {
	    {"0", 0},
	    {"-0", 0},
	    {"1", 65536},
	    {"-1", -65536},
	    {"0.5", 32768},
	    {"0.53", 34734},
	    {"-0.53", -34734},
	    {"0.00001525878906250", 1},	       /* 2^-16, one ulp */
	    {"0.000007629394531249999999", 0}, /* just below a tie */
	    {"0.00000762939453125", 1},	       /* a tie: away from 0 */
	    {"-0.00000762939453125", -1},
	    {"0.00002288818359375", 2}, /* 1.5 ulp: tie, away from 0 */
	    {"-0.00002288818359375", -2},
	    {"1.99999999999999999999999999", 131072},
	    {"127.99999", 8388607},
	    {"-127.99999", -8388607},
	    {"3.14159265358979", 205887},
	    {"0000002.25", 147456},
	    {"0.1", 6554}, /* 6553.6 */
	    {"-0.1", -6554},
	    {"0.3", 19661}, /* 19660.8 */
	};
	size_t i;
	for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		evo_status st;
		long long q = q16_of(cases[i].text, &st);
		if (q != cases[i].q16) {
			TEST_WRITE("    number ");
			TEST_WRITE(cases[i].text);
			TEST_WRITE("\n");
		}
		CHECK_EQ_INT(q, cases[i].q16);
	}
}

TEST(net_any_order_after_header)
{
	CHECK_OK(PARSE(evo_netdesc_parse,
		       "OUTPUTS:2\nINPUTS:0\nnode:7:relu:3\nNODE:9:Step:-2\n"
		       "link:7:9:1.5\noutput:9\nlink:9:7:0.25\noutput:7\n",
		       &nd));
	CHECK_EQ_INT(nd.n_in, 0);
	CHECK_EQ_INT(nd.n_out, 2);
	CHECK_EQ_INT(nd.out_id[0], 9);
	CHECK_EQ_INT(nd.out_id[1], 7);
	CHECK_EQ_INT(nd.node[1].act, EVO_ACT_STEP);
	CHECK_EQ_INT(nd.link[1].weight, 16384);
	/* outputs:0 and no nodes is a valid (empty) network */
	CHECK_OK(PARSE(evo_netdesc_parse, "inputs:3 outputs:0", &nd));
	CHECK_EQ_INT(nd.n_in, 3);
}

TEST(net_limits_reached_exactly)
{
	/* EVO_NET_MAX_FANIN links into one node is allowed. */
	static char text[1 << 16];
	size_t n = 0;
	int i;
	n += (size_t)sprintf(text + n, "inputs:1 outputs:1 node:1:identity:0 "
				       "output:1\n");
	for (i = 2; i < EVO_NET_MAX_FANIN + 1; i++)
		n += (size_t)sprintf(text + n, "node:%d:identity:0\n", i);
	for (i = 0; i < EVO_NET_MAX_FANIN + 1; i++)
		if (i != 1)
			n += (size_t)sprintf(text + n, "link:%d:1:0.5\n", i);
	CHECK_OK(evo_netdesc_parse(text, n, "fanin", &nd, &err));
	CHECK_EQ_INT(nd.n_links, EVO_NET_MAX_FANIN);
}

int main(void)
{
	RUN(tutorial_botdesc);
	RUN(botdesc_crlf_bom_blanks);
	RUN(botdesc_zero_actuators_and_verbatim_params);
	RUN(tutorial_vardesc);
	RUN(vardesc_empty_and_case);
	RUN(tutorial_collect);
	RUN(tutorial_move_forward);
	RUN(tutorial_avoid);
	RUN(ades_crlf_bom_case_one_line);
	RUN(tutorial_simbatch);
	RUN(simbatch_mixed);
	RUN(simbatch_many_warnings);
	RUN(simbatch_method_keys_are_kept);
	RUN(simbatch_team_lines_repeat);
	RUN(simbatch_tables);
	RUN(simbatch_every_whole_key_is_checked_at_its_bounds);
	RUN(simbatch_ranges_of_each_kind);
	RUN(net_file);
	RUN(net_numbers_round_exactly);
	RUN(net_any_order_after_header);
	RUN(net_limits_reached_exactly);
	return test_summary();
}
