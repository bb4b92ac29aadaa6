/* `evo run --record PATH`: a run recorded frame by frame, as PNG files in
 * a folder or as a video file made by ffmpeg (Debian's `ffmpeg`, when it
 * is installed) from the raw frames piped to it (docs/running.md,
 * "Recording a run"). */
#ifndef EVO_RECORD_H
#define EVO_RECORD_H

#include "base/err.h"
#include "viewer/raster.h"

typedef struct evo_recorder evo_recorder;

/* 1 when path names a video (.mp4, .webm, .mkv, .avi, .gif), else 0 (a
 * folder of frames). */
int evo_record_is_video(const char *path);

/* Start recording w x h frames at path: a video at fps frames a second,
 * or a folder (made if missing) of frame-000001.png, ... NULL with err
 * (ffmpeg missing for a video, a folder that cannot be made). */
evo_recorder *evo_record_open(const char *path, int w, int h, int fps,
			      evo_err *err);

/* Add one frame (w x h as opened). 0, or -1 with err. */
int evo_record_frame(evo_recorder *r, const evo_raster *im, evo_err *err);

/* Finish (ffmpeg writes its file) and free; *frames gets the count. 0, or
 * -1 with err (ffmpeg failed). Safe on NULL. */
int evo_record_close(evo_recorder *r, long *frames, evo_err *err);

#endif
