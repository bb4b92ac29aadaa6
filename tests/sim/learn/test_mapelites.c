/* MAPELITES end to end (lua/learn/mapelites.lua through learn.c and
 * learnsim.lua): a run keeps its archive in the run folder (archive.csv,
 * one .net an elite that evo loads, archive.png), log.csv gains coverage
 * and QD-score columns that agree with archive.csv, and the same seed gives
 * the same log, archive and champion with one thread, two threads and two
 * MPI ranks, and after a SIGKILL and --resume. The heatmap's cells have the
 * colours of their fitness (sim/learn/heatmap.c), and a CVT archive's
 * picture colours each centroid's region by its elite's fitness. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "base/fileio.h"
#include "harness.h"
#include "learn/heatmap.h"
#include "support/cli.h"
#include "viewer/png.h"
#include "viewer/viewer.h"

/* A copy of Avoid whose skill has one hidden layer, and a MAPELITES task:
 * `ticks` a repetition, a 20 x 20 grid over the final position, batches
 * of 24 from an initial 30, wide variation so the bots spread. */
static void make_mind(const char *name, int numgen, int ticks)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/%s && cp -r minds/Avoid %s/%s/ && "
			    "sed -i 's/^layers:0$/layers:1/' "
			    "%s/%s/Avoid/Skills/Avoid/Avoid.ades && "
			    "printf 'TYPE:LEARNSIM\\nBOTMODEL:BotType8\\n"
			    "MASTERSKILL:Avoid\\nLEARNINGSKILL:Avoid\\n"
			    "ENV:EXP_Avoid\\nLEARNINGMETHOD:MAPELITES\\n"
			    "NUMGEN:%d\\nEVALREP:1\\nTICKLIM:%d\\n"
			    "POPSIZE:24\\nMAPELITES_INITIAL_BATCH:30\\n"
			    "MAPELITES_CELLS:20\\nMAPELITES_SIGMA_ISO:0.5\\n"
			    "MAPELITES_QD_OFFSET:-100\\n' "
			    "> %s/%s/Avoid/Tasks/Small.simbatch",
			    cli_tmp, name, cli_tmp, name, cli_tmp, name, numgen,
			    ticks, cli_tmp, name),
		     0);
}

static int train(const char *name, const char *launch, const char *extra)
{
	return cli_sh("%s %s run %s/%s/Avoid/Tasks/Small.simbatch --seed 11 "
		      "--run %s/%s/run %s > %s/%s/out.txt 2>&1",
		      launch, cli_evo, cli_tmp, name, cli_tmp, name, extra,
		      cli_tmp, name);
}

static char *log_of(const char *name)
{
	char run[256];
	snprintf(run, sizeof run, "%s/%s/run", cli_tmp, name);
	return cli_fitness_log(run);
}

/* The log, archive, champion and checkpoint of `name` are those of
 * `reference`. */
static void same_run(const char *name, const char *reference)
{
	static const char *const files[] = {"run/archive.csv",
					    "run/checkpoint.lua",
					    "run/champion.net"};
	char *a = log_of(reference), *b = log_of(name);
	CHECK(a && b);
	if (a && b)
		CHECK_EQ_STR(b, a);
	free(a);
	free(b);
	for (unsigned k = 0; k < sizeof files / sizeof files[0]; k++) {
		char *x = cli_read("%s/%s/%s", cli_tmp, reference, files[k]);
		char *y = cli_read("%s/%s/%s", cli_tmp, name, files[k]);
		CHECK(x && y);
		if (x && y && strcmp(x, y) != 0) {
			printf("  %s differs\n", files[k]);
			CHECK(0);
		}
		free(x);
		free(y);
	}
}

/* The last row of log.csv: coverage and QD-score (its last two cells). */
static int last_measures(const char *name, double *coverage, double *qd)
{
	char *text = cli_read("%s/%s/run/log.csv", cli_tmp, name);
	if (!text)
		return -1;
	size_t n = strlen(text);
	while (n && text[n - 1] == '\n')
		text[--n] = 0;
	char *row = strrchr(text, '\n');
	char *comma = row ? strrchr(row, ',') : NULL;
	int ok = comma != NULL;
	if (ok) {
		*qd = atof(comma + 1);
		*comma = 0;
		*coverage = atof(strrchr(row, ',') + 1);
	}
	free(text);
	return ok ? 0 : -1;
}

TEST(the_run_folder_keeps_the_archive_and_log_measures_it)
{
	make_mind("t1", 4, 300);
	CHECK_EQ_INT(train("t1", "", "--threads 1"), 0);
	char *head = cli_read("%s/t1/run/log.csv", cli_tmp);
	CHECK(head && strstr(head, ",elapsed,metric:coverage,metric:qd_score\n"));
	free(head);
	/* archive.csv: cell, x, y, fitness, generation, 2-hidden... weights */
	char *csv = cli_read("%s/t1/run/archive.csv", cli_tmp);
	CHECK(csv && strncmp(csv, "cell,d1,d2,fitness,generation,w1,", 33) == 0);
	int rows = 0;
	double sum = 0, best = -INFINITY;
	int best_cell = 0;
	for (char *p = csv ? strchr(csv, '\n') : NULL; p && p[1];
	     p = strchr(p + 1, '\n')) {
		int cell;
		double x, y, f;
		if (sscanf(p + 1, "%d,%lf,%lf,%lf", &cell, &x, &y, &f) != 4)
			break;
		/* the cell is the grid's for its descriptor */
		int ix = (int)(x * 20), iy = (int)(y * 20);
		ix = ix > 19 ? 19 : ix;
		iy = iy > 19 ? 19 : iy;
		CHECK_EQ_INT(cell, 1 + ix + 20 * iy);
		rows++;
		sum += f + 100;
		if (f > best) {
			best = f;
			best_cell = cell;
		}
	}
	CHECK(rows > 1);
	double coverage = -1, qd = -1;
	CHECK_EQ_INT(last_measures("t1", &coverage, &qd), 0);
	CHECK(fabs(coverage - rows / 400.0) < 1e-12);
	if (fabs(qd - sum) >= 1e-9 * fabs(sum))
		printf("  qd %.17g, archive sum %.17g\n", qd, sum);
	CHECK(fabs(qd - sum) < 1e-9 * fabs(sum));
	free(csv);
	/* one .net an elite; the champion is the best elite's network */
	char *out = cli_read("%s/t1/out.txt", cli_tmp);
	char want[200];
	snprintf(want, sizeof want, "archive: %d elites in 400 cells", rows);
	CHECK_CONTAINS(out, want);
	free(out);
	CHECK_EQ_INT(cli_sh("test $(ls %s/t1/run/elites | wc -l) -eq %d",
			    cli_tmp, rows),
		     0);
	/* elites/elite-CELL.net, CELL padded to the width of cell 400, so
	 * that ls lists them in cell order */
	CHECK_EQ_INT(cli_sh("cd %s/t1/run/elites && ls | grep -vxE "
			    "'elite-[0-9]{3}[.]net' | wc -l | grep -qx 0 && "
			    "ls | sort -c",
			    cli_tmp),
		     0);
	char *elite = cli_read("%s/t1/run/elites/elite-%03d.net", cli_tmp,
			       best_cell);
	char *champ = cli_read("%s/t1/run/champion.net", cli_tmp);
	CHECK(elite && champ);
	if (elite && champ) {
		CHECK_CONTAINS(elite, "# MAP-Elites elite of cell ");
		CHECK_CONTAINS(champ, "# trained by evo: MAPELITES, seed 11");
		/* the same network after their comment lines */
		CHECK_EQ_STR(strstr(elite, "inputs:"), strstr(champ, "inputs:"));
	}
	free(elite);
	free(champ);
	/* the skill keeps its network: the result is the archive */
	CHECK_EQ_INT(cli_sh("cmp -s minds/Avoid/Skills/Avoid/Avoid.net "
			    "%s/t1/Avoid/Skills/Avoid/Avoid.net",
			    cli_tmp),
		     0);
	out = cli_read("%s/t1/out.txt", cli_tmp);
	CHECK_CONTAINS(out, "MAP-Elites keeps an archive, not one network: "
			    "Skills/Avoid/Avoid.net is left as it was; the "
			    "elite of best fitness is ");
	CHECK(out && strstr(out, "champion saved in") == NULL);
	free(out);
	/* an elite runs in its task's environment through --net */
	snprintf(want, sizeof want, "%s/t1/run/elites/elite-%03d.net", cli_tmp,
		 best_cell);
	CHECK_EQ_INT(cli_sh("cp %s/t1/Avoid/Tasks/Small.simbatch "
			    "%s/t1/Avoid/Tasks/Demo.simbatch && sed -i "
			    "'s/^TYPE:LEARNSIM$/TYPE:DEMOSIM/' "
			    "%s/t1/Avoid/Tasks/Demo.simbatch && %s run "
			    "%s/t1/Avoid/Tasks/Demo.simbatch --headless "
			    "--net Avoid=%s > %s/t1/demo.txt 2>&1",
			    cli_tmp, cli_tmp, cli_tmp, cli_evo, cli_tmp, want,
			    cli_tmp),
		     0);
	char png[256];
	snprintf(png, sizeof png, "%s/t1/run/archive.png", cli_tmp);
	CHECK(evo_file_exists(png));
}

TEST(one_thread_two_threads_and_two_ranks_give_the_same_archive)
{
	make_mind("t2", 4, 300);
	make_mind("np2", 4, 300);
	CHECK_EQ_INT(train("t2", "", "--threads 2"), 0);
	same_run("t2", "t1");
	CHECK_EQ_INT(train("np2", "mpirun --oversubscribe -np 2",
			   "--threads 1"),
		     0);
	same_run("np2", "t1");
}

static int rows_of(const char *name)
{
	char *t = cli_read("%s/%s/run/log.csv", cli_tmp, name);
	int n = t ? cli_count_lines(t, "") - 1 : 0;
	free(t);
	return n;
}

/* Runs `name` (8 generations), SIGKILLs it after its third row, resumes
 * it, and checks it ends as `reference`. */
static void kill_and_resume(const char *name, const char *reference)
{
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "exec %s run %s/%s/Avoid/Tasks/Small.simbatch --seed 11 "
		 "--threads 2 --run %s/%s/run > %s/%s/out1.txt 2>&1",
		 cli_evo, cli_tmp, name, cli_tmp, name, cli_tmp, name);
	pid_t pid = fork();
	if (pid == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	struct timespec ms = {0, 2000000};
	for (int i = 0; i < 20000 && rows_of(name) < 3; i++)
		nanosleep(&ms, NULL);
	kill(pid, SIGKILL);
	int st;
	waitpid(pid, &st, 0);
	CHECK(WIFSIGNALED(st) && WTERMSIG(st) == SIGKILL);
	CHECK(rows_of(name) >= 3 && rows_of(name) < 8);
	CHECK_EQ_INT(train(name, "", "--threads 2 --resume"), 0);
	char *out = cli_read("%s/%s/out.txt", cli_tmp, name);
	CHECK_CONTAINS(out, "resuming after generation");
	free(out);
	same_run(name, reference);
}

TEST(a_killed_run_resumes_to_the_same_archive)
{
	make_mind("kr", 8, 1500);
	make_mind("k", 8, 1500);
	CHECK_EQ_INT(train("kr", "", "--threads 2"), 0);
	kill_and_resume("k", "kr");
}

/* The coverage column of each row of `name`'s log.csv (its second last). */
static int coverages(const char *name, double *out, int max)
{
	char *text = cli_read("%s/%s/run/log.csv", cli_tmp, name);
	int n = 0;
	for (char *row = text ? strchr(text, '\n') : NULL; row && row[1] && n < max;
	     row = strchr(row + 1, '\n')) {
		char *end = strchr(row + 1, '\n');
		char *p = end ? end : row + strlen(row);
		int commas = 0;
		while (p > row && commas < 2)
			commas += *--p == ',';
		out[n++] = atof(p + 1);
	}
	free(text);
	return n;
}

/* CMA-ME's improvement emitters (MAPELITES_EMITTER:cmame, 3 emitters of
 * 8): batches of 24 after the first 30, the coverage grows, and the same
 * seed gives the same log, archive and champion with one thread, two
 * threads, two MPI ranks and after a SIGKILL and --resume. */
TEST(cmame_emitters_fill_the_archive_the_same_on_threads_ranks_and_resume)
{
	static const char *const names[] = {"c1", "c2", "cnp", "ck"};
	for (int k = 0; k < 4; k++) {
		make_mind(names[k], 8, 1500);
		CHECK_EQ_INT(cli_sh("printf 'MAPELITES_EMITTER:cmame\\n"
				    "MAPELITES_EMITTERS:3\\nMAPELITES_EMITTER_"
				    "BATCH:8\\nMAPELITES_EMITTER_SIGMA:1\\n' >> "
				    "%s/%s/Avoid/Tasks/Small.simbatch",
				    cli_tmp, names[k]),
			     0);
	}
	CHECK_EQ_INT(train("c1", "", "--threads 1"), 0);
	char *log = cli_read("%s/c1/run/log.csv", cli_tmp);
	CHECK(log && strstr(log, "\n0,") && strstr(log, ",30,0,"));
	CHECK(log && strstr(log, "\n7,") && strstr(strstr(log, "\n7,"), ",24,0,"));
	free(log);
	double cov[8];
	CHECK_EQ_INT(coverages("c1", cov, 8), 8);
	CHECK(cov[7] > cov[0]);
	CHECK_EQ_INT(train("c2", "", "--threads 2"), 0);
	same_run("c2", "c1");
	CHECK_EQ_INT(train("cnp", "mpirun --oversubscribe -np 2", "--threads 1"),
		     0);
	same_run("cnp", "c1");
	kill_and_resume("ck", "c1");
}

/* Acceptance 5: a chosen elite of a Kheperax archive runs in the viewer
 * with --net and --trail; its episode ends where the archive says (the
 * maze is deterministic), and the screenshot shows its path. */
TEST(the_viewer_shows_a_chosen_elite_and_its_path)
{
	CHECK_EQ_INT(cli_sh("mkdir -p %s/kh && cp -r minds/Kheperax %s/kh/ && "
			    "cd %s/kh/Kheperax/Tasks && sed -e "
			    "'s/^NUMGEN:.*/NUMGEN:3/' -e "
			    "'s/^POPSIZE:.*/POPSIZE:60/' -e "
			    "'s/^MAPELITES_CELLS:.*/MAPELITES_CELLS:10/' "
			    "Kheperax-MAPELITES.simbatch > Small.simbatch",
			    cli_tmp, cli_tmp, cli_tmp),
		     0);
	CHECK_EQ_INT(cli_sh("%s run %s/kh/Kheperax/Tasks/Small.simbatch --seed 5 "
			    "--run %s/kh/run > %s/kh/out.txt 2>&1",
			    cli_evo, cli_tmp, cli_tmp, cli_tmp),
		     0);
	/* Kheperax's best fitness is the least effort, a bot that stands
	 * still: the skill's network is not replaced by it */
	CHECK_EQ_INT(cli_sh("cmp -s minds/Kheperax/Skills/Kheperax/Kheperax.net "
			    "%s/kh/Kheperax/Skills/Kheperax/Kheperax.net",
			    cli_tmp),
		     0);
	/* the elite that ended farthest from the start (0.15, 0.15) */
	char *csv = cli_read("%s/kh/run/archive.csv", cli_tmp);
	int cell = 0;
	double far = -1, ex = 0, ey = 0;
	for (char *p = csv ? strchr(csv, '\n') : NULL; p && p[1];
	     p = strchr(p + 1, '\n')) {
		int c;
		double x, y;
		if (sscanf(p + 1, "%d,%lf,%lf", &c, &x, &y) != 3)
			break;
		double d = (x - 0.15) * (x - 0.15) + (y - 0.15) * (y - 0.15);
		if (d > far) {
			far = d;
			cell = c;
			ex = x;
			ey = y;
		}
	}
	free(csv);
	CHECK(far > 0.01);
	char shot[256], out[4096];
	snprintf(shot, sizeof shot, "%s/kh/elite.png", cli_tmp);
	int rc = cli_capture(out, sizeof out,
			     "%s run %s/kh/Kheperax/Tasks/Kheperax-DEMO.simbatch "
			     "-nog --net Kheperax=%s/kh/run/elites/elite-%03d.net "
			     "--trail --ticks 250 --screenshot %s",
			     cli_evo, cli_tmp, cli_tmp, cell, shot);
	CHECK_EQ_INT(rc, 0);
	rc = cli_capture(out, sizeof out,
			 "%s run %s/kh/Kheperax/Tasks/Kheperax-DEMO.simbatch "
			 "--headless --net Kheperax=%s/kh/run/elites/elite-%03d.net",
			 cli_evo, cli_tmp, cli_tmp, cell);
	CHECK_EQ_INT(rc, 0);
	char want[100];
	snprintf(want, sizeof want, "behaviour (%.6f, %.6f)", ex, ey);
	CHECK_CONTAINS(out, want);
	evo_png_image im;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_png_read(shot, &im, &err), 0);
	long trail = 0;
	for (long i = 0; im.pixels && i < (long)im.w * im.h; i++) {
		const uint8_t *px = im.pixels + i * im.channels;
		trail += ((uint32_t)px[0] << 16 | (uint32_t)px[1] << 8 | px[2]) ==
			 EVO_VIEW_TRAIL;
	}
	/* a path of at least a tenth of the arena, 2 px wide or more */
	CHECK(trail > 100);
	evo_png_image_free(&im);
}

/* A 3 x 2 grid: its cells are drawn where they belong, the lowest fitness
 * dark, the highest yellow, an empty cell grey. */
TEST(heatmap_cells_have_the_colours_of_their_fitness)
{
	char path[256];
	snprintf(path, sizeof path, "%s/h.png", cli_tmp);
	double v[6] = {0, 0.5, 1, NAN, 2, NAN};
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_heatmap_write(path, "t", 3, 2, v, &err), 0);
	evo_png_image png;
	CHECK_EQ_INT(evo_png_read(path, &png, &err), 0);
	/* the plot is 500 px square at (60, 40); cell (x, y) spans x * 500 / 3
	 * across and rows from the bottom, 250 px each */
	struct {
		int x, y;
		uint32_t rgb;
	} want[] = {{0, 0, evo_heatmap_colour(0)},
		    {1, 0, evo_heatmap_colour(0.25)},
		    {2, 0, evo_heatmap_colour(0.5)},
		    {0, 1, EVO_HEATMAP_EMPTY},
		    {1, 1, evo_heatmap_colour(1)},
		    {2, 1, EVO_HEATMAP_EMPTY}};
	for (int k = 0; k < 6; k++) {
		int px = 60 + want[k].x * 500 / 3 + 80;
		int py = 40 + 500 - want[k].y * 250 - 125;
		const uint8_t *p =
		    png.pixels + png.channels * ((size_t)py * png.w + px);
		uint32_t rgb = (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
		CHECK_EQ_INT((int)rgb, (int)want[k].rgb);
	}
	CHECK_EQ_INT((int)evo_heatmap_colour(0), 0x440154);
	CHECK_EQ_INT((int)evo_heatmap_colour(1), 0xFDE725);
	evo_png_image_free(&png);
}

/* The colour of archive.png of run `name` at descriptor (x, y): the plot
 * is 500 px square at (60, 40), y up. */
static uint32_t colour_at(const evo_png_image *png, double x, double y)
{
	int px = 60 + (int)(x * 500), py = 40 + 499 - (int)(y * 500);
	px = px > 559 ? 559 : px;
	py = py < 40 ? 40 : py;
	const uint8_t *p = png->pixels + png->channels * ((size_t)py * png->w + px);
	return (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
}

/* A CVT archive of 2-D descriptors (the final position) with 24 cells:
 * archive.png colours each centroid's region by its elite's fitness, on
 * the scale from the archive's lowest fitness to its highest, and an
 * empty region grey; the pixel at each centroid (centroids.csv) shows
 * it. */
TEST(a_cvt_archive_picture_colours_each_region_by_its_elite)
{
	make_mind("cvt", 3, 200);
	CHECK_EQ_INT(cli_sh("printf 'MAPELITES_ARCHIVE:cvt\nMAPELITES_CVT_CELLS:24\n"
			    "MAPELITES_CVT_SAMPLES:3000\n' >> "
			    "%s/cvt/Avoid/Tasks/Small.simbatch",
			    cli_tmp),
		     0);
	CHECK_EQ_INT(train("cvt", "", "--threads 2"), 0);
	double fit[25];
	for (int c = 0; c < 25; c++)
		fit[c] = NAN;
	double lo = INFINITY, hi = -INFINITY;
	char *csv = cli_read("%s/cvt/run/archive.csv", cli_tmp);
	CHECK(csv != NULL);
	for (char *p = csv ? strchr(csv, '\n') : NULL; p && p[1];
	     p = strchr(p + 1, '\n')) {
		int cell;
		double x, y, f;
		if (sscanf(p + 1, "%d,%lf,%lf,%lf", &cell, &x, &y, &f) != 4 ||
		    cell < 1 || cell > 24)
			break;
		fit[cell] = f;
		lo = f < lo ? f : lo;
		hi = f > hi ? f : hi;
	}
	free(csv);
	CHECK(lo < hi);
	char *cen = cli_read("%s/cvt/run/centroids.csv", cli_tmp);
	CHECK(cen && strncmp(cen, "cell,c1,c2\n", 11) == 0);
	char png_path[256];
	snprintf(png_path, sizeof png_path, "%s/cvt/run/archive.png", cli_tmp);
	evo_png_image png;
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_png_read(png_path, &png, &err), 0);
	int seen = 0, filled = 0, empty = 0;
	for (char *p = cen ? strchr(cen, '\n') : NULL; p && p[1];
	     p = strchr(p + 1, '\n')) {
		int cell;
		double x, y;
		if (sscanf(p + 1, "%d,%lf,%lf", &cell, &x, &y) != 3 || cell < 1 ||
		    cell > 24)
			break;
		seen++;
		uint32_t want = isnan(fit[cell])
				    ? EVO_HEATMAP_EMPTY
				    : evo_heatmap_colour((fit[cell] - lo) / (hi - lo));
		filled += !isnan(fit[cell]);
		empty += isnan(fit[cell]) != 0;
		if (colour_at(&png, x, y) != want)
			printf("  cell %d at (%g, %g): %06x, expected %06x\n",
			       cell, x, y, colour_at(&png, x, y), want);
		CHECK_EQ_INT((int)colour_at(&png, x, y), (int)want);
	}
	CHECK_EQ_INT(seen, 24);
	CHECK(filled > 1 && empty > 0);
	evo_png_image_free(&png);
	free(cen);
}

int main(void)
{
	if (cli_setup("mapelites"))
		return 1;
	setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
	setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
	RUN(the_run_folder_keeps_the_archive_and_log_measures_it);
	RUN(one_thread_two_threads_and_two_ranks_give_the_same_archive);
	RUN(a_killed_run_resumes_to_the_same_archive);
	RUN(cmame_emitters_fill_the_archive_the_same_on_threads_ranks_and_resume);
	RUN(heatmap_cells_have_the_colours_of_their_fitness);
	RUN(a_cvt_archive_picture_colours_each_region_by_its_elite);
	RUN(the_viewer_shows_a_chosen_elite_and_its_path);
	cli_cleanup();
	return test_summary();
}
