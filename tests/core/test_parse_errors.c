/* Tests the error reports of core/src/parse_*.c: one row per malformed
 * input, with the status and the message ("file:line: " and a distinctive
 * part of the wording) each must give. */
#include <string.h>

#include "evo/formats.h"
#include "harness.h"

enum { BOTDESC, VARDESC, ADES, SIMBATCH, NET };

typedef struct error_case {
	int format;
	const char *text;
	evo_status status;
	const char *prefix;  /* the message starts with this: "file:line: " */
	const char *wording; /* and contains this */
} error_case;

/* The tutorial's Avoid.ades declaring 16 inputs but listing 15: the
 * output:4 line turns up where input 16 was expected. */
#define AVOID_16                                                               \
	"Avoid\ninput:16\nSE:US_1\nSE:US_2\nSE:US_3\nSE:US_4\nSE:US_5\n"       \
	"SE:US_6\nSE:US_7\nSE:US_8\nSE:US_9\nSE:US_10\nSD:US_10\nSD:US_1\n"    \
	"SD:US_2\nVA: VAR_SIN\nSE:DOF\noutput:4\nSK:moveForward\n"             \
	"SK:turnLeft\nSK:turnRight\nSK:moveBackwards\nneural\nlayers:2\n"

#define NAME64                                                                 \
	"N123456789012345678901234567890123456789012345678901234567890123"

#define NET_HEAD "inputs:2\noutputs:1\nnode:2:sigmoid:0\n"

static const error_case cases[] = {
    /* ---- .botdesc ---- */
    {BOTDESC, "", EVO_ERR_MISSING, "b.botdesc:1: ",
     "expected the keyword SENSORS, found the end of the file"},
    {BOTDESC, "# only a comment\n\n", EVO_ERR_MISSING, "b.botdesc:2: ",
     "expected the keyword SENSORS, found the end of the file"},
    {BOTDESC, "# bot\nS1:proxSensor\nSENSORS\n", EVO_ERR_SYNTAX,
     "b.botdesc:2: ",
     "expected the keyword SENSORS first, found "
     "'S1:proxSensor'"},
    {BOTDESC, "ACTUATORS\nM1:propeller\n", EVO_ERR_MISSING,
     "b.botdesc:1: ", "expected the keyword SENSORS first, found 'ACTUATORS'"},
    {BOTDESC, "SENSORS\nS1:proxSensor\n", EVO_ERR_MISSING, "b.botdesc:2: ",
     "expected the keyword ACTUATORS after the sensors, found the end"},
    {BOTDESC, "SENSORS\nS1:proxSensor\nS2:prox\nS1:camera\nACTUATORS\n",
     EVO_ERR_NAME, "b.botdesc:4: ",
     "expected a new sensor name, found 'S1' again (first on line 2)"},
    {BOTDESC, "SENSORS\nACTUATORS\nM1:propeller M1:wheel\n", EVO_ERR_NAME,
     "b.botdesc:3: ", "found 'M1' again (first on line 3)"},
    {BOTDESC, "SENSORS\n:proxSensor\nACTUATORS\n", EVO_ERR_SYNTAX,
     "b.botdesc:2: ", "expected a sensor name, found ':proxSensor'"},
    {BOTDESC, "SENSORS\nS1:\nACTUATORS\n", EVO_ERR_SYNTAX,
     "b.botdesc:2: ", "expected a sensor type, found 'S1:'"},
    {BOTDESC, "SENSORS\nS1\nACTUATORS\n", EVO_ERR_SYNTAX,
     "b.botdesc:2: ", "expected a sensor entry name:type, found 'S1'"},
    {BOTDESC, "SENSORS\n" NAME64 ":proxSensor\nACTUATORS\n", EVO_ERR_LIMIT,
     "b.botdesc:2: ",
     "expected a sensor name of at most 63 bytes, found one of 64 bytes"},
    {BOTDESC, "SENSORS\nACTUATORS\nSENSORS\n", EVO_ERR_SYNTAX, "b.botdesc:3: ",
     "expected SENSORS only once, found it again (first "
     "on line 1)"},
    {BOTDESC, "SENSORS\nS1:a\x01\nACTUATORS\n", EVO_ERR_SYNTAX,
     "b.botdesc:2: ", "found a control byte (code 1)"},

    /* ---- .vardesc ---- */
    {VARDESC, "VAR_SIN:TickWaveSinVariableModul\n", EVO_ERR_NAME,
     "v.vardesc:1: ",
     "unknown variable type 'TickWaveSinVariableModul', did you mean "
     "TickWaveSinVariableModule?"},
    {VARDESC, "\n\nA:Countervariable\n", EVO_ERR_NAME, "v.vardesc:3: ",
     "did you mean CounterVariableModule? (expected VariableModule, "
     "TickWaveSinVariableModule or CounterVariableModule)"},
    {VARDESC, "A:VariableModule\nB:VariableModule A:CounterVariableModule",
     EVO_ERR_NAME, "v.vardesc:2: ",
     "expected a new variable name, found 'A' again (first on line 1)"},
    {VARDESC, "A:VariableModule:3\n", EVO_ERR_SYNTAX, "v.vardesc:1: ",
     "expected a variable entry name:type, found 'A:VariableModule:3'"},
    {VARDESC, "VAR_BASE\n", EVO_ERR_SYNTAX,
     "v.vardesc:1: ", "expected a variable entry name:type, found 'VAR_BASE'"},
    {VARDESC, "A: \n", EVO_ERR_SYNTAX,
     "v.vardesc:1: ", "expected a variable type after ':', found 'A:'"},
    {VARDESC, "\t: VariableModule\n", EVO_ERR_SYNTAX,
     "v.vardesc:1: ", "expected a variable name, found ': VariableModule'"},

    /* ---- .ades ---- */
    {ADES, "# nothing\n", EVO_ERR_MISSING,
     "s.ades:1: ", "expected the skill name, found the end of the file"},
    {ADES, "input:1\nSE:S1\noutput:0\nneural\n", EVO_ERR_MISSING,
     "s.ades:1: ", "expected the skill name first, found 'input:1'"},
    {ADES, AVOID_16, EVO_ERR_COUNT, "Avoid.ades:18: ",
     "expected an input line TYPE:name (input 16 of 16), found "
     "'output:4'"},
    {ADES, "Collect\ninput:1\nSE:SENSOBJ\nSE:SENSDZ\noutput:0\nneural\n",
     EVO_ERR_COUNT, "s.ades:4: ",
     "expected output:COUNT, found an input line beyond the 1 that input:1 "
     "declares: 'SE:SENSDZ'"},
    {ADES, "S\ninput:2\nSE:a\n", EVO_ERR_COUNT, "s.ades:3: ",
     "expected an input line TYPE:name (input 2 of 2), found the end of "
     "the file"},
    {ADES, "S\ninput:two\n", EVO_ERR_SYNTAX, "s.ades:2: ",
     "expected input:COUNT with a whole number 0..64, found 'input:two'"},
    {ADES, "S\ninput:65\n", EVO_ERR_LIMIT, "s.ades:2: ",
     "expected input:COUNT with a whole number 0..64, found 'input:65'"},
    {ADES, "S\nneural\n", EVO_ERR_SYNTAX,
     "s.ades:2: ", "expected input:COUNT, found 'neural'"},
    {ADES, "S\ninput:1\nXX:foo\n", EVO_ERR_NAME, "s.ades:3: ",
     "expected an input type (SE, SD, VA or VD), found 'XX' in 'XX:foo'"},
    {ADES, "S\ninput:1\nMO:MotL\n", EVO_ERR_NAME, "s.ades:3: ",
     "expected an input type (SE, SD, VA or VD), found the output type "
     "'MO' in 'MO:MotL'"},
    {ADES, "S\ninput:0\noutput:1\nSD:x\n", EVO_ERR_NAME, "s.ades:4: ",
     "expected an output type (MO, SK or VA), found the input type 'SD'"},
    {ADES, "S\ninput:1\nSE:\n", EVO_ERR_SYNTAX,
     "s.ades:3: ", "expected an input name, found 'SE:'"},
    {ADES, "S\ninput:0\noutput:0\nneuronal\n", EVO_ERR_NAME, "s.ades:4: ",
     "expected the internal function type neural or hardCoded, found "
     "'neuronal'"},
    {ADES, "S\ninput:0\noutput:0\n", EVO_ERR_MISSING, "s.ades:3: ",
     "expected the internal function type (neural or hardCoded), found "
     "the end of the file"},
    {ADES, "S\ninput:0\noutput:1\nMO:a\nMO:b\nneural\n", EVO_ERR_COUNT,
     "s.ades:5: ",
     "(neural or hardCoded), found an output line beyond "
     "the 1 that output:1 declares: 'MO:b'"},
    {ADES, "S\ninput:0\noutput:2\nMO:a\nhardCoded\n", EVO_ERR_COUNT,
     "s.ades:5: ",
     "expected an output line TYPE:name (output 2 of 2), found "
     "'hardCoded'"},
    {ADES, "moveForward\ninput:0\noutput:0\nhardCoded\n", EVO_ERR_MISSING,
     "s.ades:4: ",
     "expected class:NAME after 'hardCoded', found the end of the file"},
    {ADES, "moveForward\ninput:0\noutput:0\nhardCoded\nlayers:2\n",
     EVO_ERR_MISSING,
     "s.ades:5: ", "expected class:NAME after 'hardCoded', found 'layers:2'"},
    {ADES, "S\ninput:0\noutput:0\nneural\nlayers:abc\n", EVO_ERR_SYNTAX,
     "s.ades:5: ",
     "expected layers:N with a whole number 0..16, found 'layers:abc'"},
    {ADES, "S\ninput:0\noutput:0\nneural\nlayers:17\n", EVO_ERR_LIMIT,
     "s.ades:5: ",
     "expected layers:N with a whole number 0..16, found 'layers:17'"},
    {ADES, "S\ninput:0\noutput:0\nneural\nlayers:2\nextra\n", EVO_ERR_SYNTAX,
     "s.ades:6: ",
     "expected the end of the file after layers:N, found 'extra'"},
    {ADES, "S\ninput:0\noutput:0\nhardCoded class:X\nclass:Y\n", EVO_ERR_SYNTAX,
     "s.ades:5: ",
     "expected the end of the file after class:NAME, found 'class:Y'"},
    {ADES, "S\ninput:0\noutput:0\nneural\nsize:3\n", EVO_ERR_SYNTAX,
     "s.ades:5: ",
     "expected layers:N or the end of the file after 'neural', found "
     "'size:3'"},

    /* ---- .simbatch ---- */
    {SIMBATCH, "TYPE:LEARNSIM\nLEARNINGMETHOD NEAT\n", EVO_ERR_SYNTAX,
     "t.simbatch:2: ", "expected KEY:VALUE, found 'LEARNINGMETHOD' (no ':')"},
    {SIMBATCH, "TYPE:LEARNSIM\nENV:\n", EVO_ERR_SYNTAX,
     "t.simbatch:2: ", "expected a value after 'ENV:', found nothing"},
    {SIMBATCH, ":LEARNSIM\n", EVO_ERR_SYNTAX,
     "t.simbatch:1: ", "expected a key before ':', found ':LEARNSIM'"},
    {SIMBATCH, "NUMGEN:abc\n", EVO_ERR_SYNTAX, "t.simbatch:1: ",
     "NUMGEN: expected a whole number from 1 to 1000000, found 'abc'"},
    {SIMBATCH, "EVALREP:3 NUMGEN:0\n", EVO_ERR_SYNTAX, "t.simbatch:1: ",
     "NUMGEN: expected a whole number from 1 to 1000000, found '0'"},
    {SIMBATCH, "\nTICKLIM:-5\n", EVO_ERR_SYNTAX, "t.simbatch:2: ",
     "TICKLIM: expected a whole number from 1 to 10000000, found '-5'"},
    {SIMBATCH, "POPSIZE:3000000000\n", EVO_ERR_LIMIT,
     "t.simbatch:1: ",
     "POPSIZE: expected a whole number from 1 to 10000, found '3000000000'"},
    {SIMBATCH, "SEED:-1\n", EVO_ERR_SYNTAX, "t.simbatch:1: ",
     "SEED: expected a whole number from 0 to 2147483647, found '-1'"},
    {SIMBATCH, "TYPE:LEARNSIMS\n", EVO_ERR_NAME, "t.simbatch:1: ",
     "TYPE: expected DEMOSIM, LEARNSIM, LEARNSIMCONTINUOUS, DEMO2DSIMMULTI, "
     "LEARN2DSIMMULTI, DEMO3DSIM, LEARN3DSIM, DEMO3DSIMMULTI, "
     "LEARN3DSIMMULTI, DEMOREMOTE, DEMOREMOTESIM, "
     "LEARNREMOTESIM or OPENENDED, found 'LEARNSIMS'; did you mean "
     "LEARNSIM?"},
    {SIMBATCH, "ENV:EXP_Avoid\nNUMGEN:5\n\nnumgen:6\n", EVO_ERR_NAME,
     "t.simbatch:4: ",
     "expected each key once, found NUMGEN again (first on line 2)"},

    /* ---- .net ---- */
    {NET, "outputs:1\nnode:2:sigmoid:0\n", EVO_ERR_MISSING, "x.net:2: ",
     "expected inputs:COUNT before the first node, output or link line, "
     "found 'node:2:sigmoid:0'"},
    {NET, "outputs:1\n", EVO_ERR_MISSING,
     "x.net:1: ", "expected inputs:COUNT, found the end of the file"},
    {NET, NET_HEAD "output:2\nlink:0:3:1.0\n", EVO_ERR_NAME, "x.net:5: ",
     "expected a link into a node declared above, found undeclared node 3"},
    {NET, NET_HEAD "output:2\nlink:5:2:1.0\n", EVO_ERR_NAME, "x.net:5: ",
     "expected a link from an input or a node declared above, found "
     "undeclared node 5"},
    {NET, NET_HEAD "output:2\nlink:2:1:0.5\n", EVO_ERR_NAME,
     "x.net:5: ", "expected a link into a node, found a link into input 1"},
    {NET, NET_HEAD "node:2:tanh:1\n", EVO_ERR_NAME, "x.net:4: ",
     "expected a new node id, found node 2 again (first on line 3)"},
    {NET, NET_HEAD "node:1:tanh:1\n", EVO_ERR_NAME,
     "x.net:4: ", "expected a node id of at least 2 (ids 0..1 are the inputs)"},
    {NET, "inputs:2 outputs:1\nnode:2:sigmod:0\n", EVO_ERR_NAME, "x.net:2: ",
     "expected an activation name, found 'sigmod'; did you mean sigmoid? "
     "(known: identity sigmoid neat_sigmoid tanh relu step clamped "
     "gauss)"},
    {NET, NET_HEAD "output:2\nlink:0:2:128\n", EVO_ERR_LIMIT,
     "x.net:5: ", "expected a weight with |weight| < 128, found '128'"},
    {NET, NET_HEAD "output:2\nlink:0:2:-200.5\n", EVO_ERR_LIMIT,
     "x.net:5: ", "expected a weight with |weight| < 128, found '-200.5'"},
    {NET, NET_HEAD "output:2\nlink:0:2:127.999999\n", EVO_ERR_LIMIT,
     "x.net:5: ", "found '127.999999'"},
    {NET, "inputs:2 outputs:1\nnode:2:sigmoid:130\n", EVO_ERR_LIMIT,
     "x.net:2: ", "expected a bias with |bias| < 128, found '130'"},
    {NET, NET_HEAD "output:2\nlink:0:2:1.2.3\n", EVO_ERR_SYNTAX, "x.net:5: ",
     "expected a decimal number like -1.25 for the weight, found '1.2.3'"},
    {NET, NET_HEAD "output:2\nlink:0:2:--1\n", EVO_ERR_SYNTAX,
     "x.net:5: ", "for the weight, found '--1'"},
    {NET, NET_HEAD "output:2\nlink:0:2:\n", EVO_ERR_SYNTAX,
     "x.net:5: ", "for the weight, found '' in 'link:0:2:'"},
    {NET, NET_HEAD "output:2\nlink:0:2:3e-2\n", EVO_ERR_SYNTAX,
     "x.net:5: ", "for the weight, found '3e-2'"},
    {NET, "inputs:2 outputs:1\nnode:2:sigmoid:.5\n", EVO_ERR_SYNTAX,
     "x.net:2: ", "for the bias, found '.5'"},
    {NET, NET_HEAD "output:2\nlink:0:2:1.\n", EVO_ERR_SYNTAX,
     "x.net:5: ", "for the weight, found '1.'"},
    {NET, "inputs:2\noutputs:2\nnode:2:sigmoid:0\noutput:2\n", EVO_ERR_COUNT,
     "x.net:4: ", "expected 2 output:ID lines (outputs:2), found 1"},
    {NET, NET_HEAD "node:3:relu:0\noutput:2\noutput:3\n", EVO_ERR_COUNT,
     "x.net:6: ",
     "expected 1 output:ID line (outputs:1), found one more: 'output:3'"},
    {NET, NET_HEAD "output:2\nlink:0:2:1\nlink:1:2:1\nlink:0:2:-1\n",
     EVO_ERR_NAME, "x.net:7: ",
     "expected each link once, found link 0:2 again (first on line 5)"},
    {NET, NET_HEAD "output:0\n", EVO_ERR_NAME, "x.net:4: ",
     "expected an output that is a node declared above, found input 0"},
    {NET, NET_HEAD "output:2\ninputs:3\n", EVO_ERR_SYNTAX, "x.net:5: ",
     "expected inputs:COUNT and outputs:COUNT before any node, output or "
     "link line, found 'inputs:3'"},
    {NET, "inputs:2\ninputs:2\n", EVO_ERR_SYNTAX, "x.net:2: ",
     "expected inputs:COUNT once, found it again (first on line 1)"},
    {NET, NET_HEAD "output:2\nlink:0:70000:1\n", EVO_ERR_SYNTAX, "x.net:5: ",
     "expected link:FROM:TO:WEIGHT with a node id 0..65535, found "
     "'70000'"},
    {NET, NET_HEAD "output:2\nlink:0:2\n", EVO_ERR_SYNTAX,
     "x.net:5: ", "expected link:FROM:TO:WEIGHT, found 'link:0:2'"},
    {NET, NET_HEAD "output:2\nweight:0:2:1\n", EVO_ERR_SYNTAX, "x.net:5: ",
     "expected an inputs:, outputs:, node:, output: or link: line, found "
     "'weight:0:2:1'"},
};

static evo_botdesc bd;
static evo_vardesc vd;
static evo_ades ad;
static evo_simbatch sb;
static evo_netdesc nd;

/* The file name a row's message is expected to start with. */
static const char *file_for(const error_case *c)
{
	static const char *const names[] = {"b.botdesc", "v.vardesc", "s.ades",
					    "t.simbatch", "x.net"};
	if (c->format == ADES && strncmp(c->prefix, "Avoid.ades", 10) == 0)
		return "Avoid.ades";
	return names[c->format];
}

static evo_status parse(const error_case *c, evo_diag *err)
{
	const char *f = file_for(c);
	size_t n = strlen(c->text);
	switch (c->format) {
	case BOTDESC:
		return evo_botdesc_parse(c->text, n, f, &bd, err);
	case VARDESC:
		return evo_vardesc_parse(c->text, n, f, &vd, err);
	case ADES:
		return evo_ades_parse(c->text, n, f, &ad, err);
	case SIMBATCH:
		return evo_simbatch_parse(c->text, n, f, &sb, err);
	default:
		return evo_netdesc_parse(c->text, n, f, &nd, err);
	}
}

TEST(every_malformed_input_is_reported)
{
	size_t i;
	for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		const error_case *c = &cases[i];
		evo_diag err;
		evo_status st;
		int before = test_current_failed;
		test_current_failed = 0;
		err.msg[0] = 0;
		st = parse(c, &err);
		CHECK_EQ_INT(st, c->status);
		CHECK(strncmp(err.msg, c->prefix, strlen(c->prefix)) == 0);
		CHECK_CONTAINS(err.msg, c->wording);
		CHECK(memchr(err.msg, 0, sizeof err.msg) != NULL);
		if (test_current_failed) {
			TEST_WRITE("    row ");
			test_write_uint((unsigned long)i);
			TEST_WRITE(": ");
			TEST_WRITE(err.msg);
			TEST_WRITE("\n");
		}
		test_current_failed |= before;
	}
	CHECK(sizeof cases / sizeof cases[0] >= 40);
}

TEST(unknown_simbatch_key_is_a_warning)
{
	static const char text[] =
	    "TYPE:LEARNSIM\nNUMGENS:50 EVALREP:3\nBOTMODL:BotType6\n";
	evo_diag err;
	err.msg[0] = 0;
	CHECK_EQ_INT(
	    evo_simbatch_parse(text, sizeof text - 1, "t.simbatch", &sb, &err),
	    EVO_OK);
	CHECK_EQ_INT(sb.n_pairs, 2);
	CHECK_EQ_INT(sb.n_warnings, 2);
	CHECK_EQ_STR(sb.warning[0].msg, "t.simbatch:2: unknown key 'NUMGENS' "
					"ignored; did you mean NUMGEN?");
	CHECK_EQ_STR(sb.warning[1].msg, "t.simbatch:3: unknown key 'BOTMODL' "
					"ignored; did you mean BOTMODEL?");
}

TEST(long_found_text_is_cut)
{
	static char text[4096];
	evo_diag err;
	size_t i;
	memcpy(text, "SENSORS\nS1", 10);
	for (i = 10; i < sizeof text; i++)
		text[i] = 'x';
	CHECK_EQ_INT(evo_botdesc_parse(text, sizeof text, "b", &bd, &err),
		     EVO_ERR_SYNTAX);
	CHECK_CONTAINS(err.msg, "b:2: expected a sensor entry name:type, "
				"found 'S1xxxx");
	CHECK_CONTAINS(err.msg, "xxx...'");
	CHECK(strlen(err.msg) < 120);
}

TEST(nul_byte_is_reported)
{
	static const char text[] = "Collect\ninput:0\noutput:0\nneu\0ral\n";
	evo_diag err;
	CHECK_EQ_INT(evo_ades_parse(text, sizeof text - 1, "s.ades", &ad, &err),
		     EVO_ERR_SYNTAX);
	CHECK_EQ_STR(err.msg, "s.ades:4: expected text, found a control byte "
			      "(code 0); is this a text file?");
}

TEST(limits_are_errors)
{
	static char text[1 << 18];
	evo_diag err;
	size_t n = 0;
	int i;
	n += (size_t)sprintf(text, "SENSORS\n");
	for (i = 0; i <= EVO_MAX_SENSORS; i++)
		n += (size_t)sprintf(text + n, "S%d:prox\n", i);
	CHECK_EQ_INT(evo_botdesc_parse(text, n, "b", &bd, &err), EVO_ERR_LIMIT);
	CHECK_CONTAINS(err.msg, "b:130: expected at most 128 sensors");
	CHECK_EQ_INT(bd.n_sensors, EVO_MAX_SENSORS);

	n = 0;
	for (i = 0; i <= EVO_MAX_VARIABLES; i++)
		n += (size_t)sprintf(text + n, "V%d:VariableModule\n", i);
	CHECK_EQ_INT(evo_vardesc_parse(text, n, "v", &vd, &err), EVO_ERR_LIMIT);
	CHECK_CONTAINS(err.msg, "v:65: expected at most 64 variables");

	n = (size_t)sprintf(text, "inputs:1 outputs:0\n");
	for (i = 1; i <= EVO_NET_MAX_NODES + 1; i++)
		n += (size_t)sprintf(text + n, "node:%d:relu:0\n", i);
	CHECK_EQ_INT(evo_netdesc_parse(text, n, "x", &nd, &err), EVO_ERR_LIMIT);
	CHECK_CONTAINS(err.msg, "x:514: expected at most 512 nodes");

	/* fan-in: EVO_NET_MAX_FANIN + 1 links into node 1000 */
	n = (size_t)sprintf(text, "inputs:1 outputs:0\nnode:1000:relu:0\n");
	for (i = 1; i <= EVO_NET_MAX_FANIN; i++)
		n += (size_t)sprintf(text + n, "node:%d:relu:0\n", i);
	for (i = 0; i <= EVO_NET_MAX_FANIN; i++)
		n += (size_t)sprintf(text + n, "link:%d:1000:1\n", i);
	CHECK_EQ_INT(evo_netdesc_parse(text, n, "x", &nd, &err), EVO_ERR_LIMIT);
	CHECK_CONTAINS(err.msg, "expected at most 256 links into node 1000");

	/* links: 17 nodes, each with 256 links in from 256 sources */
	n = (size_t)sprintf(text, "inputs:64 outputs:0\n");
	for (i = 64; i < 64 + 256; i++)
		n += (size_t)sprintf(text + n, "node:%d:relu:0\n", i);
	for (i = 0; i <= EVO_NET_MAX_LINKS; i++)
		n += (size_t)sprintf(text + n, "link:%d:%d:1\n", i % 256,
				     64 + i / 256);
	CHECK_EQ_INT(evo_netdesc_parse(text, n, "x", &nd, &err), EVO_ERR_LIMIT);
	CHECK_CONTAINS(err.msg, "expected at most 4096 links");
	CHECK_EQ_INT(nd.n_links, EVO_NET_MAX_LINKS);
}

int main(void)
{
	RUN(every_malformed_input_is_reported);
	RUN(unknown_simbatch_key_is_a_warning);
	RUN(long_found_text_is_cut);
	RUN(nul_byte_is_reported);
	RUN(limits_are_errors);
	return test_summary();
}
