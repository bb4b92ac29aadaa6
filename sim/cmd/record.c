/* Recording frames (sim/cmd/record.h). */
#define _POSIX_C_SOURCE 200809L
#include "cmd/record.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

struct evo_recorder {
	char path[1024];
	int w, h;
	FILE *pipe; /* ffmpeg's stdin; NULL for a folder */
	long frames;
};

static const char *extension(const char *path)
{
	const char *slash = strrchr(path, '/');
	const char *dot = strrchr(path, '.');
	return dot && (!slash || dot > slash) ? dot + 1 : "";
}

int evo_record_is_video(const char *path)
{
	static const char *const ext[] = {"mp4", "webm", "mkv", "avi", "gif"};
	for (size_t i = 0; i < sizeof ext / sizeof ext[0]; i++)
		if (strcmp(extension(path), ext[i]) == 0)
			return 1;
	return 0;
}

/* The path for the shell, in single quotes. */
static void shell_quote(char *out, size_t cap, const char *s)
{
	size_t at = 0;
	out[at++] = '\'';
	for (; *s && at + 6 < cap; s++) {
		if (*s == '\'') {
			memcpy(out + at, "'\\''", 4);
			at += 4;
		} else {
			out[at++] = *s;
		}
	}
	out[at++] = '\'';
	out[at] = 0;
}

static evo_recorder *open_video(evo_recorder *r, int fps, evo_err *err)
{
	if (system("command -v ffmpeg > /dev/null 2>&1") != 0) {
		evo_fail(err,
			 "evo run --record %s: a video is made by ffmpeg, which "
			 "is not installed (Debian: apt-get install ffmpeg); "
			 "--record FOLDER saves the frames as PNG files "
			 "without it",
			 r->path);
		free(r);
		return NULL;
	}
	char q[2100], cmd[2400];
	shell_quote(q, sizeof q, r->path);
	/* yuv420p, which every player reads (the frames' sides are even);
	 * a GIF gets one palette made for the run's colours, and each frame
	 * stores only the rectangle that changed (the world mostly holds
	 * still): 51 frames of 1024 x 720 take 0.5 MB, not ffmpeg's
	 * default 14 MB */
	snprintf(cmd, sizeof cmd,
		 "ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgb24 "
		 "-s %dx%d -r %d -i - %s%s",
		 r->w, r->h, fps,
		 strcmp(extension(r->path), "gif") == 0
		     ? "-filter_complex \"split[a][b];[a]palettegen="
		       "stats_mode=diff[p];[b][p]paletteuse=dither=bayer:"
		       "bayer_scale=5:diff_mode=rectangle\" "
		     : "-pix_fmt yuv420p ",
		 q);
	/* ffmpeg gone mid-run must be an error, not SIGPIPE */
	signal(SIGPIPE, SIG_IGN);
	r->pipe = popen(cmd, "w");
	if (!r->pipe) {
		evo_fail(err, "evo run --record %s: cannot start ffmpeg",
			 r->path);
		free(r);
		return NULL;
	}
	return r;
}

evo_recorder *evo_record_open(const char *path, int w, int h, int fps,
			      evo_err *err)
{
	evo_recorder *r = calloc(1, sizeof *r);
	if (!r) {
		evo_fail(err, "out of memory");
		return NULL;
	}
	if (strlen(path) >= sizeof r->path - 32) {
		evo_fail(err, "evo run --record: the path is too long");
		free(r);
		return NULL;
	}
	snprintf(r->path, sizeof r->path, "%s", path);
	r->w = w;
	r->h = h;
	if (evo_record_is_video(path))
		return open_video(r, fps, err);
	if (mkdir(path, 0777) != 0 && errno != EEXIST) {
		evo_fail(err, "evo run --record %s: cannot make the folder: %s",
			 path, strerror(errno));
		free(r);
		return NULL;
	}
	struct stat st;
	if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode)) {
		evo_fail(err,
			 "evo run --record %s: not a folder (a video's name "
			 "ends in .mp4, .webm, .mkv, .avi or .gif)",
			 path);
		free(r);
		return NULL;
	}
	return r;
}

int evo_record_frame(evo_recorder *r, const evo_raster *im, evo_err *err)
{
	r->frames++;
	if (r->pipe) {
		size_t n = (size_t)im->w * (size_t)im->h * 3;
		if (fwrite(im->pixels, 1, n, r->pipe) != n)
			return evo_fail(err,
					"evo run --record %s: ffmpeg stopped "
					"taking frames (its message is above)",
					r->path);
		return 0;
	}
	char file[1100];
	snprintf(file, sizeof file, "%s/frame-%06ld.png", r->path, r->frames);
	return evo_raster_save_png(im, file, err);
}

int evo_record_close(evo_recorder *r, long *frames, evo_err *err)
{
	if (!r)
		return 0;
	int rc = 0;
	if (frames)
		*frames = r->frames;
	if (r->pipe) {
		int st = pclose(r->pipe);
		if (!(WIFEXITED(st) && WEXITSTATUS(st) == 0))
			rc = evo_fail(err,
				      "evo run --record %s: ffmpeg failed (its "
				      "message is above)",
				      r->path);
	}
	free(r);
	return rc;
}
