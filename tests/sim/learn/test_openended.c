/* OPENENDED end to end (lua/learn/openended.lua over sim/learn/learn.c,
 * the generator lua/envs/GEN_Maze.lua), on a copy of minds/OpenMaze with
 * a budget of 8 batches: ANNECS never falls and ends above 0; the seed
 * maze's solution path is 3 cells (by hand: two steps along x, one along
 * y in a 3 x 2 grid); every admitted maze is solved by the agent that
 * solved it when admitted (replayed by evo run), and retention.csv counts
 * them all, and `evo run --env N` shows one with its solver; gallery.png
 * draws a thumbnail of each (up to 24); retention after every batch by
 * each maze's known solvers finds what full checks find; one thread and
 * two give the same log, retention.csv and envs.csv; a run killed with
 * SIGKILL and resumed gives the same ones; a generator's error is reported at its file:line, and in the
 * loop it runs in a sandbox with a scene script's limits and require: an
 * endless mutate, one that allocates without end and a require of a
 * module linked out of the mind folder each end the run at its line. */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "harness.h"
#include "learn/gallery.h"
#include "support/cli.h"
#include "viewer/png.h"
#include "viewer/viewer.h"

static void make_mind(const char *name)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/%s && cp -r minds/OpenMaze %s/%s/ && "
			    "rm -rf %s/%s/OpenMaze/Runs && "
			    "mkdir -p %s/%s/OpenMaze/Envs",
			    cli_tmp, name, cli_tmp, name, cli_tmp, name, cli_tmp,
			    name),
		     0);
}

static int run(const char *name, const char *task, const char *extra)
{
	return cli_sh("timeout 120 %s run %s/%s/OpenMaze/Tasks/%s.simbatch --seed 3 "
		      "--generations 8 --no-save --run %s/%s/run %s > "
		      "%s/%s/out.txt 2>&1",
		      cli_evo, cli_tmp, name, task, cli_tmp, name, extra,
		      cli_tmp, name);
}

/* Column `col` (0-based) of each row of log.csv after its header. */
static int column(const char *log, int col, double *v, int cap)
{
	const char *p = strchr(log, '\n');
	int n = 0;
	while (p && p[1] && n < cap) {
		p++;
		const char *f = p;
		for (int k = 0; k < col && f; k++) {
			f = strchr(f, ',');
			f = f ? f + 1 : NULL;
		}
		if (!f)
			return -1;
		v[n++] = strtod(f, NULL);
		p = strchr(p, '\n');
	}
	return n;
}

TEST(annecs_rises_and_the_seed_maze_is_three_cells)
{
	make_mind("a");
	CHECK_EQ_INT(run("a", "OpenMaze", "--threads 2"), 0);
	char *log = cli_read("%s/a/run/log.csv", cli_tmp);
	CHECK(log && strstr(log, ",metric:annecs,metric:largest,"));
	double annecs[16], largest[16];
	CHECK_EQ_INT(column(log ? log : "", 9, annecs, 16), 8);
	CHECK_EQ_INT(column(log ? log : "", 10, largest, 16), 8);
	CHECK(annecs[0] == 1 && largest[0] == 3);
	for (int i = 1; i < 8; i++)
		CHECK(annecs[i] >= annecs[i - 1] && largest[i] >= largest[i - 1]);
	CHECK(annecs[7] > annecs[0]);
	free(log);
	char *envs = cli_read("%s/a/run/envs.csv", cli_tmp);
	CHECK(envs && strstr(envs, "1,0,3,0,\"{h=2,w=3,walls={},}\""));
	free(envs);
}

/* Environment `genome` (text) as a DEMOSIM task's: GEN_Maze with that
 * maze as its seed, in Envs/Fixed.lua and Tasks/Fixed.simbatch of a. */
static void fixed_env(const char *genome)
{
	char env[8192];
	snprintf(env, sizeof env,
		 "local openended = require 'lib.openended'\n"
		 "local gen = {}\n"
		 "for k, v in pairs(require('envs.GEN_Maze').generator) do "
		 "gen[k] = v end\n"
		 "gen.seed = function() return openended.decode('%s') end\n"
		 "return openended.env(gen)\n",
		 genome);
	CHECK_EQ_INT(cli_write(env, "%s/a/OpenMaze/Envs/Fixed.lua", cli_tmp),
		     0);
	CHECK_EQ_INT(cli_write("TYPE:DEMOSIM\nBOTMODEL:MazeBot\nBOTNAME:Maze\n"
			       "MASTERSKILL:Maze\nENV:Fixed\n",
			       "%s/a/OpenMaze/Tasks/Fixed.simbatch", cli_tmp),
		     0);
}

/* Every admitted maze, replayed alone with the agent that solved it when
 * it was admitted (solvers/env-NNNN.net), is solved; and the champion is
 * the solver of the largest. */
TEST(every_admitted_maze_is_solved_by_its_solver)
{
	char *envs = cli_read("%s/a/run/envs.csv", cli_tmp);
	CHECK(envs != NULL);
	const char *p = envs ? strchr(envs, '\n') : NULL;
	int n = 0, solved = 0, best_id = 0;
	double best_size = -1;
	while (p && p[1]) {
		p++;
		int id = atoi(p);
		const char *size = strchr(p, ',');
		size = size ? strchr(size + 1, ',') : NULL;
		const char *q = strchr(p, '"');
		const char *end = q ? strchr(q + 1, '"') : NULL;
		if (!size || !q || !end)
			break;
		double sz = strtod(size + 1, NULL);
		if (sz > best_size) {
			best_size = sz;
			best_id = id;
		}
		char genome[4096];
		snprintf(genome, sizeof genome, "%.*s", (int)(end - q - 1),
			 q + 1);
		fixed_env(genome);
		char out[4096] = "";
		cli_capture(out, sizeof out,
			    "%s run %s/a/OpenMaze/Tasks/Fixed.simbatch --headless "
			    "--net Maze=%s/a/run/solvers/env-%04d.net 2>&1",
			    cli_evo, cli_tmp, cli_tmp, id);
		n++;
		if (strstr(out, "solved"))
			solved++;
		else
			printf("  environment %d (%s): %s", id, genome, out);
		p = strchr(end, '\n');
	}
	CHECK(n >= 5);
	CHECK_EQ_INT(solved, n);
	free(envs);
	char *champion = cli_read("%s/a/run/champion.net", cli_tmp);
	char *solver = cli_read("%s/a/run/solvers/env-%04d.net", cli_tmp, best_id);
	/* the same network, with another comment line */
	CHECK(champion && solver &&
	      strcmp(strchr(champion, '\n'), strchr(solver, '\n')) == 0);
	free(champion);
	free(solver);
	/* retention, checked after every batch: the last row counts every
	 * admitted maze */
	char *ret = cli_read("%s/a/run/retention.csv", cli_tmp);
	char want[64];
	snprintf(want, sizeof want, "\n7,%d,", n);
	CHECK(ret &&
	      strstr(ret, "batch,admitted,retained,lost,evaluations,full\n") ==
		      ret &&
	      strstr(ret, want));
	free(ret);
}

/* Pixels of colour rgb in the size x size square at (x0, y0) of img. */
static int count_colour(const evo_png_image *img, int x0, int y0, int size,
			uint32_t rgb)
{
	int n = 0;
	for (int y = y0; y < y0 + size && y < img->h; y++)
		for (int x = x0; x < x0 + size && x < img->w; x++) {
			const uint8_t *p =
			    img->pixels + ((size_t)y * img->w + x) * img->channels;
			n += ((uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2]) ==
			     rgb;
		}
	return n;
}

/* gallery.png after the run: a thumbnail per admitted maze up to 24, six
 * to a row (8 pixels around 180 x 180 thumbnails, a 14-pixel caption
 * under each, a 22-pixel title), each with the maze's border drawn in the
 * viewer's obstacle grey and its caption under it. */
TEST(the_gallery_shows_the_admitted_mazes)
{
	char *envs = cli_read("%s/a/run/envs.csv", cli_tmp);
	int n = -1;
	for (const char *p = envs; p && *p; p++)
		n += *p == '\n';
	free(envs);
	int k = n < 24 ? n : 24, cols = k < 6 ? k : 6, rows = (k + 5) / 6;
	CHECK(k >= 5);
	char path[1200];
	snprintf(path, sizeof path, "%s/a/run/gallery.png", cli_tmp);
	evo_png_image img;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_png_read(path, &img, &err), 0);
	if (err.msg[0]) {
		printf("  %s\n", err.msg);
		return;
	}
	CHECK_EQ_INT(img.w, 8 + cols * (EVO_GALLERY_THUMB + 8));
	CHECK_EQ_INT(img.h, 22 + rows * (EVO_GALLERY_THUMB + 14 + 8));
	int drawn = 0, captioned = 0;
	for (int i = 0; i < k; i++) {
		int x = 8 + (i % 6) * (EVO_GALLERY_THUMB + 8);
		int y = 22 + (i / 6) * (EVO_GALLERY_THUMB + 14 + 8);
		drawn += count_colour(&img, x, y, EVO_GALLERY_THUMB,
				      EVO_VIEW_OBSTACLE) > 100;
		captioned += count_colour(&img, x, y + EVO_GALLERY_THUMB, 14,
					  0xD8DCE2u) > 10;
	}
	CHECK_EQ_INT(drawn, k);
	CHECK_EQ_INT(captioned, k);
	free(img.pixels);
}

/* evo run TASK --env N shows admitted environment N with its solver: the
 * largest one is solved there as in the replay above; a number the run
 * did not admit is refused with envs.csv's path. */
TEST(evo_run_env_shows_an_admitted_maze_with_its_solver)
{
	char id[32] = "";
	CHECK_EQ_INT(cli_capture(id, sizeof id,
				 "sort -t, -k3,3g -s %s/a/run/envs.csv | "
				 "tail -1 | cut -d, -f1",
				 cli_tmp),
		     0);
	id[strcspn(id, "\n")] = 0;
	char out[4096] = "";
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s/a/OpenMaze/Tasks/OpenMaze.simbatch "
				 "--run %s/a/run --env %s --headless 2>&1",
				 cli_evo, cli_tmp, cli_tmp, id),
		     0);
	char want[64];
	snprintf(want, sizeof want, "with solvers/env-%04d.net", atoi(id));
	CHECK_CONTAINS(out, want);
	CHECK_CONTAINS(out, ", solved");
	/* a screenshot of it, with no TICKLIM: at the episode's end, with
	 * the episode's line, not of tick 0 */
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s/a/OpenMaze/Tasks/OpenMaze.simbatch "
				 "--run %s/a/run --env %s --headless --trail "
				 "--screenshot %s/a/env.png 2>&1",
				 cli_evo, cli_tmp, cli_tmp, id, cli_tmp),
		     0);
	CHECK(!strstr(out, "(tick 0,"));
	CHECK_CONTAINS(out, "drawn without a window");
	CHECK_CONTAINS(out, ", solved");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s/a/OpenMaze/Tasks/OpenMaze.simbatch "
				 "--run %s/a/run --env 9999 --headless 2>&1",
				 cli_evo, cli_tmp, cli_tmp),
		     1);
	CHECK_CONTAINS(out, "envs.csv: no environment 9999");
	/* no run in the task's default folder: say to give one */
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s/a/OpenMaze/Tasks/OpenMaze.simbatch "
				 "--env 1 --headless 2>&1",
				 cli_evo, cli_tmp),
		     1);
	CHECK_CONTAINS(out, "no OPENENDED run here");
	CHECK_CONTAINS(out, "--run DIR");
	/* a genome longer than --env's buffer is refused, not cut short */
	CHECK_EQ_INT(cli_sh("mkdir -p %s/long && { echo env,batch,size,genome; "
			    "printf '1,0,3,\"'; head -c 70000 /dev/zero | tr '\\0' x; "
			    "echo '\"'; } > %s/long/envs.csv",
			    cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s run %s/a/OpenMaze/Tasks/OpenMaze.simbatch "
				 "--run %s/long --env 1 --headless 2>&1",
				 cli_evo, cli_tmp, cli_tmp),
		     1);
	CHECK_CONTAINS(out, "envs.csv: environment 1's genome is longer than the "
			    "65535 bytes --env shows");
}

/* File `name` of run folders a and b: the same bytes. */
static void same_file(const char *a, const char *b, const char *name)
{
	char *fa = cli_read("%s/%s/run/%s", cli_tmp, a, name);
	char *fb = cli_read("%s/%s/run/%s", cli_tmp, b, name);
	CHECK(fa && fb && strcmp(fa, fb) == 0);
	if (fa && fb && strcmp(fa, fb) != 0)
		printf("  %s differs between runs %s and %s\n", name, a, b);
	free(fa);
	free(fb);
}

/* Retention.csv's first four columns (batch, admitted, retained, lost). */
static void retention_columns(const char *csv, char *out, size_t cap)
{
	size_t n = 0;
	int comma = 0;
	for (const char *p = csv; *p && n + 1 < cap; p++) {
		if (*p == '\n')
			comma = 0;
		else if (*p == ',')
			comma++;
		if (comma < 4 || *p == '\n')
			out[n++] = *p;
	}
	out[n] = 0;
}

/* Retention.csv's rows after its header: counted into *rows, those with
 * a maze lost into *losses, their evaluations (the fifth column) summed
 * into *evaluations. */
static void retention_rows(const char *csv, int *rows, int *losses,
			   long *evaluations)
{
	for (const char *p = strchr(csv, '\n'); p && p[1];
	     p = strchr(p + 1, '\n')) {
		int batch, admitted, retained;
		if (sscanf(p + 1, "%d,%d,%d,", &batch, &admitted, &retained) != 3)
			continue;
		(*rows)++;
		*losses += retained < admitted;
		const char *f = p + 1;
		for (int k = 0; k < 4 && f; k++) {
			f = strchr(f, ',');
			f = f ? f + 1 : NULL;
		}
		*evaluations += f ? strtol(f, NULL, 10) : 0;
	}
}

/* The bookkeeping retention (each maze's known solvers, a maze tried
 * only when its last one left) finds what a full check of every admitted
 * maze on every kept agent after every batch (OPEN_RETENTION:1) finds,
 * row for row: every maze still solved, since the last known solver of a
 * maze goes to the archive rather than out of the run; so the
 * bookkeeping tries nothing again, where the full checks cost hundreds of
 * evaluations. */
TEST(retention_after_every_batch_is_the_full_checks)
{
	make_mind("f");
	CHECK_EQ_INT(cli_sh("echo OPEN_RETENTION:1 >> "
			    "%s/f/OpenMaze/Tasks/OpenMaze.simbatch",
			    cli_tmp),
		     0);
	CHECK_EQ_INT(run("f", "OpenMaze", "--threads 1"), 0);
	char *ra = cli_read("%s/a/run/retention.csv", cli_tmp);
	char *rf = cli_read("%s/f/run/retention.csv", cli_tmp);
	CHECK(ra && rf);
	if (!ra || !rf)
		return;
	static char ca[1 << 16], cf[1 << 16];
	retention_columns(ra, ca, sizeof ca);
	retention_columns(rf, cf, sizeof cf);
	CHECK_EQ_STR(ca, cf);
	/* 8 rows, one per batch, no maze lost */
	int rows = 0, losses = 0;
	long ea = 0, ef = 0;
	retention_rows(ra, &rows, &losses, &ea);
	retention_rows(rf, &rows, &losses, &ef);
	rows /= 2;
	CHECK_EQ_INT(rows, 8);
	CHECK_EQ_INT(losses, 0);
	CHECK(ea == 0 && ef > 100);
	printf("  retention evaluations: %ld by bookkeeping, %ld by full checks\n",
	       ea, ef);
	free(ra);
	free(rf);
}

TEST(one_thread_and_two_give_the_same_log)
{
	make_mind("b");
	CHECK_EQ_INT(run("b", "OpenMaze", "--threads 1"), 0);
	char a[1024], b[1024];
	snprintf(a, sizeof a, "%s/a/run", cli_tmp);
	snprintf(b, sizeof b, "%s/b/run", cli_tmp);
	char *la = cli_fitness_log(a), *lb = cli_fitness_log(b);
	CHECK(la && lb && strcmp(la, lb) == 0);
	free(la);
	free(lb);
	same_file("a", "b", "retention.csv");
	same_file("a", "b", "envs.csv");
}

TEST(a_killed_and_resumed_run_gives_the_same_log)
{
	make_mind("k");
	char cmd[2048], out[1024];
	snprintf(out, sizeof out, "%s/k/out.txt", cli_tmp);
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/k/OpenMaze/Tasks/OpenMaze.simbatch --seed 3 "
		 "--generations 8 --no-save --threads 2 --run %s/k/run > %s "
		 "2>&1",
		 cli_evo, cli_tmp, cli_tmp, out);
	int st;
	double s;
	CHECK_EQ_INT(cli_stop(cmd, out, "gen 3/8", 0.0, SIGKILL, &st, &s), 0);
	CHECK(WIFSIGNALED(st) && WTERMSIG(st) == SIGKILL);
	CHECK_EQ_INT(run("k", "OpenMaze", "--threads 1 --resume"), 0);
	char *o = cli_read("%s/k/out.txt", cli_tmp);
	CHECK(o && strstr(o, "resuming after batch"));
	free(o);
	char a[1024], k[1024];
	snprintf(a, sizeof a, "%s/a/run", cli_tmp);
	snprintf(k, sizeof k, "%s/k/run", cli_tmp);
	char *la = cli_fitness_log(a), *lk = cli_fitness_log(k);
	CHECK(la && lk && strcmp(la, lk) == 0);
	free(la);
	free(lk);
	same_file("a", "k", "retention.csv");
	same_file("a", "k", "envs.csv");
}

/* A generator of the user's own in Envs/, whose mutate raises: the run
 * stops with the generator's file:line. */
TEST(a_generator_error_is_reported_at_its_line)
{
	make_mind("e");
	CHECK_EQ_INT(cli_sh("sed 's/^function gen.mutate(g, rng)$/&\\n"
			    "\\terror(\"broken mutate\")/' "
			    "lua/envs/GEN_Maze.lua > %s/e/OpenMaze/Envs/Bad.lua",
			    cli_tmp),
		     0);
	CHECK_EQ_INT(cli_sh("sed 's/^ENV:GEN_Maze$/ENV:Bad/' "
			    "%s/e/OpenMaze/Tasks/OpenMaze.simbatch > "
			    "%s/e/OpenMaze/Tasks/Bad.simbatch",
			    cli_tmp, cli_tmp),
		     0);
	char line[64] = "";
	CHECK_EQ_INT(cli_capture(line, sizeof line,
				 "grep -n 'broken mutate' %s/e/OpenMaze/Envs/Bad.lua "
				 "| cut -d: -f1",
				 cli_tmp),
		     0);
	line[strcspn(line, "\n")] = 0;
	CHECK(atoi(line) > 1);
	CHECK(run("e", "Bad", "--threads 1") != 0);
	char *o = cli_read("%s/e/out.txt", cli_tmp);
	char want[128];
	snprintf(want, sizeof want, "Envs/Bad.lua:%s: broken mutate", line);
	CHECK(o && strstr(o, want));
	if (o && !strstr(o, want))
		fputs(o, stdout);
	free(o);
}

/* A generator whose episodes depend on their seed (Flaky: GEN_Maze's
 * solved, but only when the episode's math.random draws below 0.5) loses
 * mazes: the full check after every batch (OPEN_RETENTION:1) tries every
 * admitted maze afresh and finds some that no agent kept solves that
 * batch. retention.csv's row names them, and the run's line says the same
 * numbers: a loss is reported, never hidden. */
TEST(a_lost_maze_is_reported)
{
	make_mind("lo");
	CHECK_EQ_INT(cli_sh("sed 's/^return openended.env(gen)$/local solved0 = "
			    "gen.solved\\nfunction gen.solved(s, b, g) return "
			    "solved0(s, b, g) and math.random() < 0.5 end\\n&/' "
			    "lua/envs/GEN_Maze.lua > %s/lo/OpenMaze/Envs/Flaky.lua && "
			    "sed 's/^ENV:GEN_Maze$/ENV:Flaky/' "
			    "%s/lo/OpenMaze/Tasks/OpenMaze.simbatch > "
			    "%s/lo/OpenMaze/Tasks/Flaky.simbatch && "
			    "echo OPEN_RETENTION:1 >> %s/lo/OpenMaze/Tasks/Flaky.simbatch",
			    cli_tmp, cli_tmp, cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(run("lo", "Flaky", "--threads 2"), 0);
	char *ret = cli_read("%s/lo/run/retention.csv", cli_tmp);
	char *out = cli_read("%s/lo/out.txt", cli_tmp);
	CHECK(ret && out);
	if (!ret || !out) {
		free(ret);
		free(out);
		return;
	}
	/* the first row with a loss, and the line printed after its batch */
	int found = 0;
	for (const char *p = strchr(ret, '\n'); p && p[1] && !found;
	     p = strchr(p + 1, '\n')) {
		int batch, admitted, retained;
		char lost[256] = "";
		if (sscanf(p + 1, "%d,%d,%d,%255[0-9 ]", &batch, &admitted,
			   &retained, lost) < 3 ||
		    retained == admitted)
			continue;
		found = 1;
		char want[512];
		int n = admitted - retained;
		for (char *c = lost; *c; c++)
			if (*c == ' ')
				*c = ',';
		char listed[300] = "";
		for (const char *c = lost; *c; c++) {
			size_t k = strlen(listed);
			if (*c == ',')
				snprintf(listed + k, sizeof listed - k, ", ");
			else
				snprintf(listed + k, sizeof listed - k, "%c", *c);
		}
		snprintf(want, sizeof want,
			 "retention after batch %d: %d of the %d environments "
			 "admitted %s no longer solved by any agent kept (%s; "
			 "retention.csv)",
			 batch, n, admitted, n == 1 ? "is" : "are", listed);
		CHECK(strstr(out, want));
		if (!strstr(out, want))
			printf("  want: %s\n%s", want, out);
	}
	CHECK(found);
	free(ret);
	free(out);
}

/* A generator without one of its functions is refused by evo check,
 * naming it, before any run; one whose size is not a number ends the run
 * with the generator named, not at a line of evo's own library. */
TEST(a_generator_missing_a_function_or_giving_a_bad_size_is_named)
{
	make_mind("m");
	CHECK_EQ_INT(cli_sh("sed 's/^function gen.solved(/function gen.solvd(/' "
			    "lua/envs/GEN_Maze.lua > %s/m/OpenMaze/Envs/NoSolved.lua && "
			    "sed 's/^ENV:GEN_Maze$/ENV:NoSolved/' "
			    "%s/m/OpenMaze/Tasks/OpenMaze.simbatch > "
			    "%s/m/OpenMaze/Tasks/NoSolved.simbatch",
			    cli_tmp, cli_tmp, cli_tmp),
		     0);
	char out[4096] = "";
	int rc = cli_capture(out, sizeof out, "%s check %s/m/OpenMaze/Tasks/NoSolved.simbatch 2>&1",
			     cli_evo, cli_tmp);
	CHECK(rc != 0);
	CHECK(strstr(out, "Envs/NoSolved.lua:") &&
	      strstr(out, "the generator has no function solved"));
	if (!strstr(out, "no function solved"))
		fputs(out, stdout);
	CHECK_EQ_INT(cli_sh("sed 's/^gen.size = gen.path_length$/"
			    "gen.size = function() return \"big\" end/' "
			    "lua/envs/GEN_Maze.lua > %s/m/OpenMaze/Envs/BadSize.lua && "
			    "sed 's/^ENV:GEN_Maze$/ENV:BadSize/' "
			    "%s/m/OpenMaze/Tasks/OpenMaze.simbatch > "
			    "%s/m/OpenMaze/Tasks/BadSize.simbatch",
			    cli_tmp, cli_tmp, cli_tmp),
		     0);
	CHECK(run("m", "BadSize", "--threads 1") != 0);
	char *o = cli_read("%s/m/out.txt", cli_tmp);
	CHECK(o && strstr(o, "Envs/BadSize.lua: the generator's size returned "
			     "string, not a number"));
	if (o && !strstr(o, "size returned"))
		fputs(o, stdout);
	free(o);
}

/* The loop runs a generator in a sandbox, as the workers do: a mutate
 * that opens a file stops at its line, io being absent there. */
TEST(a_generator_cannot_reach_files_from_the_loop)
{
	make_mind("s");
	CHECK_EQ_INT(cli_sh("sed 's/^function gen.mutate(g, rng)$/&\\n"
			    "\\tio.open(\"\\/etc\\/hostname\")/' "
			    "lua/envs/GEN_Maze.lua > %s/s/OpenMaze/Envs/Leak.lua && "
			    "sed 's/^ENV:GEN_Maze$/ENV:Leak/' "
			    "%s/s/OpenMaze/Tasks/OpenMaze.simbatch > "
			    "%s/s/OpenMaze/Tasks/Leak.simbatch",
			    cli_tmp, cli_tmp, cli_tmp),
		     0);
	char line[64] = "";
	CHECK_EQ_INT(cli_capture(line, sizeof line,
				 "grep -n 'io.open' %s/s/OpenMaze/Envs/Leak.lua "
				 "| cut -d: -f1",
				 cli_tmp),
		     0);
	line[strcspn(line, "\n")] = 0;
	CHECK(atoi(line) > 1);
	CHECK(run("s", "Leak", "--threads 1") != 0);
	char *o = cli_read("%s/s/out.txt", cli_tmp);
	char want[128];
	snprintf(want, sizeof want, "Envs/Leak.lua:%s: attempt to index a nil "
		 "value (global 'io')", line);
	CHECK(o && strstr(o, want));
	if (o && !strstr(o, want))
		fputs(o, stdout);
	free(o);
}

/* Envs/NAME.lua: GEN_Maze with `code` as the first line of its mutate,
 * and Tasks/NAME.simbatch naming it (plus `keys`); the line of `code`. */
static int bad_generator(const char *dir, const char *name, const char *code,
			 const char *keys)
{
	make_mind(dir);
	FILE *f = fopen("lua/envs/GEN_Maze.lua", "r");
	char path[512];
	snprintf(path, sizeof path, "%s/%s/OpenMaze/Envs/%s.lua", cli_tmp, dir,
		 name);
	FILE *g = fopen(path, "w");
	CHECK(f && g);
	if (!f || !g)
		return 0;
	char buf[1024];
	int n = 0, at = 0;
	while (fgets(buf, sizeof buf, f)) {
		fputs(buf, g);
		n++;
		if (strcmp(buf, "function gen.mutate(g, rng)\n") == 0) {
			fprintf(g, "\t%s\n", code);
			at = ++n;
		}
	}
	fclose(f);
	fclose(g);
	CHECK(at > 1);
	CHECK_EQ_INT(cli_sh("(sed 's/^ENV:GEN_Maze$/ENV:%s/' "
			    "%s/%s/OpenMaze/Tasks/OpenMaze.simbatch; printf '%s') > "
			    "%s/%s/OpenMaze/Tasks/%s.simbatch",
			    name, cli_tmp, dir, keys, cli_tmp, dir, name),
		     0);
	return at;
}

/* The run (under `timeout 120`: a generator that hangs the loop fails
 * the test) ends non-zero, its output holding "Envs/NAME.lua:LINE: "
 * then `what`. */
static void stops_at(const char *dir, const char *name, int line,
		     const char *what)
{
	int rc = run(dir, name, "--threads 1");
	CHECK(rc != 0);
	char *o = cli_read("%s/%s/out.txt", cli_tmp, dir);
	char want[300];
	snprintf(want, sizeof want, "Envs/%s.lua:%d: %s", name, line, what);
	CHECK(o && strstr(o, want));
	if (o && !strstr(o, want))
		printf("want \"%s\" in:\n%s\n", want, o);
	free(o);
}

/* The loop runs the generator under a scene script's limits
 * (docs/lua.md, "Limits"): a mutate that never returns ends the run at
 * its line with the budget of env.reset, 10,000,000 instructions. */
TEST(a_generator_that_loops_forever_stops_at_its_line)
{
	int at = bad_generator("l", "Loop", "while true do end", "");
	stops_at("l", "Loop", at,
		 "the script ran past its budget of 10000000 instructions in "
		 "mutate; an endless loop?");
}

/* A mutate that changes the genome it is given (an admitted maze would
 * no longer be the one solved) ends the run, naming the generator. */
TEST(a_generator_whose_mutate_changes_its_parent_is_stopped)
{
	int at = bad_generator("p", "InPlace", "g.w = g.w + 1", "");
	CHECK(at > 1);
	CHECK(run("p", "InPlace", "--threads 1") != 0);
	char *o = cli_read("%s/p/out.txt", cli_tmp);
	CHECK(o && strstr(o, "Envs/InPlace.lua: the generator's mutate changed "
			     "the genome it was given"));
	if (o && !strstr(o, "mutate changed"))
		fputs(o, stdout);
	free(o);
}

/* A mutate stuck in one string call that backtracks, where no count
 * hook runs, is ended by the watchdog past env.reset's 2 s. */
TEST(a_generator_stuck_in_a_pattern_stops_at_its_line)
{
	int at = bad_generator("p", "Slow",
			       "string.find((\"a\"):rep(400), \".-.-.-.-b\")",
			       "");
	stops_at("p", "Slow", at,
		 "the script ran past its time limit of 2 s in mutate, in a "
		 "call that did not return");
}

/* A mutate that allocates without end is stopped by LUAMEMORY. */
TEST(a_generator_that_allocates_without_end_stops_at_its_line)
{
	int at = bad_generator("m", "Hog",
			       "local t = {} while true do "
			       "t[#t + 1] = (\"x\"):rep(1000) .. #t end",
			       "LUAMEMORY:64\\n");
	stops_at("m", "Hog", at,
		 "the script's Lua state reached its memory limit of 64 MB "
		 "in mutate");
}

/* A module that is a link to a file out of the mind folder is refused,
 * as a scene script's is. */
TEST(a_generator_cannot_require_a_module_linked_out_of_its_folder)
{
	int at = bad_generator("ln", "Link", "require \"outside\"", "");
	CHECK_EQ_INT(cli_sh("printf 'return {}\\n' > %s/ln/outside.lua && "
			    "ln -s %s/ln/outside.lua %s/ln/OpenMaze/outside.lua",
			    cli_tmp, cli_tmp, cli_tmp),
		     0);
	stops_at("ln", "Link", at, "require 'outside': ");
	char *o = cli_read("%s/ln/out.txt", cli_tmp);
	CHECK(o && strstr(o, "leads out of"));
	free(o);
}

/* ---- development (docs/openended.md, "Development") ------------------ */

/* A copy of minds/OpenMaze whose task grows a skill after every batch
 * that admits no maze (OPEN_DEVELOP 1), one maze tried a batch, 3
 * generations of focus. */
static void make_dev_mind(const char *name)
{
	make_mind(name);
	CHECK_EQ_INT(cli_sh("sed -i 's/^OPEN_DEVELOP:.*/OPEN_DEVELOP:1/; "
			    "s/^OPEN_FOCUS:.*/OPEN_FOCUS:3/; "
			    "s/^OPEN_ENV_BATCH:.*/OPEN_ENV_BATCH:1/; "
			    "s/^OPEN_PROGRESS:.*/OPEN_PROGRESS:admitted/' "
			    "%s/%s/OpenMaze/Tasks/OpenMaze.simbatch",
			    cli_tmp, name),
		     0);
}

static int run_dev(const char *name, int gens, const char *extra)
{
	return cli_sh("timeout 300 %s run %s/%s/OpenMaze/Tasks/OpenMaze.simbatch "
		      "--seed 3 --generations %d --no-save --run %s/%s/run %s > "
		      "%s/%s/out.txt 2>&1",
		      cli_evo, cli_tmp, name, gens, cli_tmp, name, extra,
		      cli_tmp, name);
}

/* With OPEN_DEVELOP 1, a skill is added after each batch that admitted
 * no maze (log.csv's solved 0), at most OPEN_MAXSKILLS (3): the log's
 * skills column counts them, worked out here from its solved column;
 * skills.csv and the run's output name each with its batch and reason;
 * the grown mind folder's Maze.ades has one output SK:ExploreK more per
 * skill, and each skill its focus-trained network. */
TEST(development_adds_a_skill_after_batches_with_no_maze_admitted)
{
	make_dev_mind("d");
	CHECK_EQ_INT(run_dev("d", 10, "--threads 2"), 0);
	char *log = cli_read("%s/d/run/log.csv", cli_tmp);
	CHECK(log && strstr(log, ",metric:agents,metric:skills\n"));
	double solved[16], skills[16];
	CHECK_EQ_INT(column(log ? log : "", 6, solved, 16), 10);
	CHECK_EQ_INT(column(log ? log : "", 13, skills, 16), 10);
	int want = 0, first = -1;
	for (int b = 0; b < 10; b++) {
		/* not after the last batch: nothing would run with it */
		if (solved[b] == 0 && want < 3 && b < 9) {
			want++;
			if (first < 0)
				first = b;
		}
		CHECK(skills[b] == want);
	}
	CHECK(first > 0);
	free(log);
	char line[256];
	snprintf(line, sizeof line,
		 "Explore1,%d,\"no environment admitted in batches %d-%d\",3,",
		 first, first, first);
	char *csv = cli_read("%s/d/run/skills.csv", cli_tmp);
	CHECK(csv && strstr(csv, "skill,batch,reason,focus,frontier,"
				 "solved_before,solved_after\n"));
	CHECK(csv && strstr(csv, line));
	free(csv);
	snprintf(line, sizeof line,
		 "skill Explore1 added after batch %d (no environment admitted "
		 "in batches %d-%d): focused training of 3 generations",
		 first, first, first);
	char *out = cli_read("%s/d/out.txt", cli_tmp);
	CHECK(out && strstr(out, line));
	free(out);
	/* one SK: output more per skill added */
	char *ades = cli_read("%s/d/run/Mind/Skills/Maze/Maze.ades", cli_tmp);
	snprintf(line, sizeof line, "output:%d\nMO:TURN\nMO:SPEED\nSK:Explore1\n",
		 2 + want);
	CHECK(ades && strstr(ades, line));
	free(ades);
	char *net = cli_read("%s/d/run/Mind/Skills/Explore1/Explore1.net",
			     cli_tmp);
	CHECK(net && strstr(net, "# trained by evo in focus: OPENENDED, seed 3, "
				 "skill Explore1 added after batch"));
	CHECK(net && strstr(net, "\ninputs:10\noutputs:2\n"));
	free(net);
	/* evo run --env N shows a maze admitted after a skill was added with
	 * its solver, in the hierarchy of that time (Mind-K, K from envs.csv's
	 * skills column), and says so; the episode solves it */
	char id[32] = "", k[32] = "", shown[4096] = "";
	CHECK_EQ_INT(cli_capture(id, sizeof id,
				 "awk -F, 'NR > 1 && $4 > 0 { print $1; exit }' "
				 "%s/d/run/envs.csv",
				 cli_tmp),
		     0);
	CHECK_EQ_INT(cli_capture(k, sizeof k,
				 "awk -F, 'NR > 1 && $4 > 0 { print $4; exit }' "
				 "%s/d/run/envs.csv",
				 cli_tmp),
		     0);
	id[strcspn(id, "\n")] = 0;
	k[strcspn(k, "\n")] = 0;
	CHECK(atoi(id) > 1 && atoi(k) >= 1);
	CHECK_EQ_INT(cli_capture(shown, sizeof shown,
				 "%s run %s/d/OpenMaze/Tasks/OpenMaze.simbatch "
				 "--run %s/d/run --env %s --headless 2>&1",
				 cli_evo, cli_tmp, cli_tmp, id),
		     0);
	snprintf(line, sizeof line,
		 "the hierarchy it was solved with: %s/d/run/Mind-%s/Tasks/"
		 "OpenMaze.simbatch",
		 cli_tmp, k);
	CHECK_CONTAINS(shown, line);
	CHECK_CONTAINS(shown, ", solved");
	/* the master's network is the champion, with the new output */
	net = cli_read("%s/d/run/Mind/Skills/Maze/Maze.net", cli_tmp);
	snprintf(line, sizeof line, "\ninputs:10\noutputs:%d\n", 2 + want);
	CHECK(net && strstr(net, line));
	free(net);
}

/* The grown mind folder is an ordinary one: DEMOSIM runs it headless (the
 * seed maze, solved) and evo export makes its image. */
TEST(the_grown_mind_folder_runs_under_demosim_and_exports)
{
	char out[8192];
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "timeout 60 %s run %s/d/run/Mind/Tasks/Demo.simbatch "
				 "--headless 2>&1",
				 cli_evo, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "episode 1: reward");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s export %s/d/run/Mind -o %s/d/mind.bin 2>&1",
				 cli_evo, cli_tmp, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "mind image of Maze");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s check %s/d/run/Mind/Tasks/OpenMaze.simbatch 2>&1",
				 cli_evo, cli_tmp),
		     0);
	CHECK_CONTAINS(out, ": ok");
}

/* A generator of the user's own in Envs/ that requires modules of its
 * mind folder (Envs/parts/time.lua, which requires Envs/parts/base.lua):
 * the grown mind folder gets them beside the generator, and none of
 * evo's own lua/ modules it required, so DEMOSIM runs the grown folder. */
TEST(a_generator_requiring_modules_of_its_folder_grows_a_folder_that_runs)
{
	make_dev_mind("rq");
	CHECK_EQ_INT(cli_sh("cd %s/rq/OpenMaze && mkdir -p Envs/parts && "
			    "printf 'return { extra = 0 }\\n' > Envs/parts/base.lua && "
			    "printf 'local base = require \"Envs.parts.base\"\\n"
			    "return function(maze) return function(g) "
			    "return maze.ticks(g) + base.extra end end\\n' "
			    "> Envs/parts/time.lua && "
			    "printf 'local maze = require(\"envs.GEN_Maze\").generator\\n"
			    "local gen = {}\\nfor k, f in pairs(maze) do gen[k] = f end\\n"
			    "gen.ticks = require(\"Envs.parts.time\")(maze)\\n"
			    "return require(\"lib.openended\").env(gen)\\n' "
			    "> Envs/Own.lua && "
			    "sed -i 's/^ENV:GEN_Maze$/ENV:Own/' Tasks/OpenMaze.simbatch",
			    cli_tmp),
		     0);
	CHECK_EQ_INT(run_dev("rq", 3, "--threads 2"), 0);
	char *base = cli_read("%s/rq/run/Mind/Envs/parts/base.lua", cli_tmp);
	char *time = cli_read("%s/rq/run/Mind/Envs/parts/time.lua", cli_tmp);
	char *own = cli_read("%s/rq/run/Mind/Envs/Own.lua", cli_tmp);
	CHECK(base && strstr(base, "extra = 0"));
	CHECK(time && strstr(time, "require \"Envs.parts.base\""));
	CHECK(own && strstr(own, "Envs.parts.time"));
	free(base);
	free(time);
	free(own);
	CHECK(cli_sh("test -e %s/rq/run/Mind/lib || test -e %s/rq/run/Mind/envs",
		     cli_tmp, cli_tmp) != 0);
	char out[8192];
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "timeout 60 %s run %s/rq/run/Mind/Tasks/Demo.simbatch "
				 "--headless 2>&1",
				 cli_evo, cli_tmp),
		     0);
	CHECK_CONTAINS(out, "episode 1: reward");
}

/* OPEN_PROGRESS:largest counts the batches in a row whose largest solved
 * maze (log.csv's metric:largest) is no larger than before: with
 * OPEN_DEVELOP 2, a skill comes after each second such batch, at most 3,
 * worked out here from the log's largest column; the reason names the
 * largest size. */
TEST(development_by_the_largest_maze)
{
	make_dev_mind("pl");
	CHECK_EQ_INT(cli_sh("sed -i 's/^OPEN_DEVELOP:.*/OPEN_DEVELOP:2/; "
			    "s/^OPEN_PROGRESS:.*/OPEN_PROGRESS:largest/' "
			    "%s/pl/OpenMaze/Tasks/OpenMaze.simbatch",
			    cli_tmp),
		     0);
	CHECK_EQ_INT(run_dev("pl", 12, "--threads 2"), 0);
	char *log = cli_read("%s/pl/run/log.csv", cli_tmp);
	double largest[16], skills[16];
	CHECK_EQ_INT(column(log ? log : "", 10, largest, 16), 12);
	CHECK_EQ_INT(column(log ? log : "", 13, skills, 16), 12);
	free(log);
	int want = 0, idle = 0, first = -1;
	double before = 0;
	for (int b = 0; b < 12; b++) {
		idle = largest[b] > before ? 0 : idle + 1;
		before = largest[b];
		if (idle >= 2 && want < 3 && b < 11) {
			want++;
			idle = 0;
			if (first < 0)
				first = b;
		}
		CHECK(skills[b] == want);
	}
	CHECK(first > 0);
	if (first <= 0)
		return;
	char line[256];
	snprintf(line, sizeof line,
		 "Explore1,%d,\"no environment larger than %g admitted in "
		 "batches %d-%d\"",
		 first, largest[first], first - 1, first);
	char *csv = cli_read("%s/pl/run/skills.csv", cli_tmp);
	CHECK(csv && strstr(csv, line));
	if (csv && !strstr(csv, line))
		printf("  want %s in:\n%s", line, csv);
	free(csv);
}

/* Development is part of the run's determinism: one thread gives the
 * same log and skills as two, and a run killed after its first skill was
 * added resumes with the grown hierarchy to the same log and skills. */
TEST(development_gives_the_same_log_with_threads_and_resume)
{
	make_dev_mind("d1");
	CHECK_EQ_INT(run_dev("d1", 10, "--threads 1"), 0);
	make_dev_mind("dk");
	char cmd[2048], out[1024];
	snprintf(out, sizeof out, "%s/dk/out.txt", cli_tmp);
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/dk/OpenMaze/Tasks/OpenMaze.simbatch --seed 3 "
		 "--generations 10 --no-save --threads 2 --run %s/dk/run > %s "
		 "2>&1",
		 cli_evo, cli_tmp, cli_tmp, out);
	int st;
	double s;
	CHECK_EQ_INT(cli_stop(cmd, out, "skills 1 ", 0.3, SIGKILL, &st, &s), 0);
	CHECK(WIFSIGNALED(st) && WTERMSIG(st) == SIGKILL);
	char *o = cli_read("%s/dk/run/checkpoint.lua", cli_tmp);
	CHECK(o && strstr(o, "Explore1"));
	free(o);
	CHECK_EQ_INT(run_dev("dk", 10, "--threads 1 --resume"), 0);
	o = cli_read("%s/dk/out.txt", cli_tmp);
	CHECK(o && strstr(o, "resuming after batch"));
	free(o);
	const char *names[] = {"d1", "dk"};
	char *sd = cli_read("%s/d/run/skills.csv", cli_tmp);
	char dir[1024];
	snprintf(dir, sizeof dir, "%s/d/run", cli_tmp);
	char *ld = cli_fitness_log(dir);
	for (int i = 0; i < 2; i++) {
		snprintf(dir, sizeof dir, "%s/%s/run", cli_tmp, names[i]);
		char *l = cli_fitness_log(dir);
		char *sk = cli_read("%s/%s/run/skills.csv", cli_tmp, names[i]);
		CHECK(ld && l && strcmp(ld, l) == 0);
		CHECK(sd && sk && strcmp(sd, sk) == 0);
		free(l);
		free(sk);
	}
	free(ld);
	free(sd);
}

/* The line of the task file that starts with `key`, 1-based; 0: none. */
static int line_of(const char *name, const char *key)
{
	char *t = cli_read("%s/%s/OpenMaze/Tasks/OpenMaze.simbatch", cli_tmp, name);
	int line = 1, at = 0;
	for (const char *p = t; p && *p; p++) {
		if ((p == t || p[-1] == '\n') && !strncmp(p, key, strlen(key))) {
			at = line;
			break;
		}
		if (*p == '\n')
			line++;
	}
	free(t);
	return at;
}

/* An OPEN_SKILL that is no file, or no skill template, stops the run at
 * the task's OPEN_SKILL line. */
TEST(a_bad_open_skill_is_reported_at_the_tasks_line)
{
	make_mind("bs");
	CHECK_EQ_INT(cli_sh("sed -i 's|^OPEN_SKILL:.*|OPEN_SKILL:Templates/Nope.ades|' "
			    "%s/bs/OpenMaze/Tasks/OpenMaze.simbatch",
			    cli_tmp),
		     0);
	int at = line_of("bs", "OPEN_SKILL:");
	CHECK(at > 0);
	char want[512];
	CHECK(run("bs", "OpenMaze", "") != 0);
	char *o = cli_read("%s/bs/out.txt", cli_tmp);
	snprintf(want, sizeof want,
		 "OpenMaze.simbatch:%d: OPEN_SKILL Templates/Nope.ades: no such "
		 "file in the mind folder",
		 at);
	CHECK(o && strstr(o, want));
	free(o);
	CHECK_EQ_INT(cli_sh("printf 'Nope\\ninput:2\\nSE:RF_LEFT\\noutput:1\\n"
			    "MO:TURN\\nneural\\n' > %s/bs/OpenMaze/Templates/Nope.ades",
			    cli_tmp),
		     0);
	CHECK(run("bs", "OpenMaze", "") != 0);
	o = cli_read("%s/bs/out.txt", cli_tmp);
	snprintf(want, sizeof want,
		 "OpenMaze.simbatch:%d: OPEN_SKILL Templates/Nope.ades is not a "
		 "skill template: input 2 of 2 is output:1",
		 at);
	CHECK(o && strstr(o, want));
	free(o);
	CHECK_EQ_INT(cli_sh("sed -i 's/^OPEN_SKILL:.*/OPEN_SKILL:Explore.txt/' "
			    "%s/bs/OpenMaze/Tasks/OpenMaze.simbatch",
			    cli_tmp),
		     0);
	CHECK(run("bs", "OpenMaze", "") != 0);
	o = cli_read("%s/bs/out.txt", cli_tmp);
	snprintf(want, sizeof want,
		 "OpenMaze.simbatch:%d: OPEN_SKILL: expected a file name ending "
		 "in .ades",
		 at);
	CHECK(o && strstr(o, want));
	free(o);
}

int main(void)
{
	if (cli_setup("openended"))
		return 1;
	RUN(annecs_rises_and_the_seed_maze_is_three_cells);
	RUN(every_admitted_maze_is_solved_by_its_solver);
	RUN(evo_run_env_shows_an_admitted_maze_with_its_solver);
	RUN(the_gallery_shows_the_admitted_mazes);
	RUN(retention_after_every_batch_is_the_full_checks);
	RUN(one_thread_and_two_give_the_same_log);
	RUN(a_killed_and_resumed_run_gives_the_same_log);
	RUN(a_generator_error_is_reported_at_its_line);
	RUN(a_generator_missing_a_function_or_giving_a_bad_size_is_named);
	RUN(a_generator_cannot_reach_files_from_the_loop);
	RUN(a_generator_that_loops_forever_stops_at_its_line);
	RUN(a_generator_whose_mutate_changes_its_parent_is_stopped);
	RUN(a_generator_stuck_in_a_pattern_stops_at_its_line);
	RUN(a_generator_that_allocates_without_end_stops_at_its_line);
	RUN(a_generator_cannot_require_a_module_linked_out_of_its_folder);
	RUN(development_adds_a_skill_after_batches_with_no_maze_admitted);
	RUN(development_by_the_largest_maze);
	RUN(a_lost_maze_is_reported);
	RUN(the_grown_mind_folder_runs_under_demosim_and_exports);
	RUN(a_generator_requiring_modules_of_its_folder_grows_a_folder_that_runs);
	RUN(development_gives_the_same_log_with_threads_and_resume);
	RUN(a_bad_open_skill_is_reported_at_the_tasks_line);
	cli_cleanup();
	return test_summary();
}
