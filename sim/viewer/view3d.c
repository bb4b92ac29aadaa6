/* The DEMO3DSIM view (sim/viewer/view3d.h): SDL2 for the window and its
 * events, OpenGL 1.x (fixed functions, as Mesa's llvmpipe gives under
 * Xvfb) for the world, the 2D viewer's panel beside it as pixels. Both
 * libraries are loaded when the view opens (viewer/sdl_load.h). Without
 * a window, the same drawing goes to Mesa's EGL off screen
 * (viewer/egl_offscreen.h): only the context differs. */
#define _GNU_SOURCE /* dl_iterate_phdr, RTLD_NODELETE */
#include "viewer/view3d.h"

#include <dlfcn.h>
#include <link.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "viewer/egl_offscreen.h"
#include "viewer/png.h"
#include "viewer/raster.h"
#include "viewer/sdl_load.h"
#include "viewer/viewer.h"
#include "viewer/viewer_internal.h"

struct evo_view3d {
	SDL_Window *window; /* NULL off screen */
	SDL_GLContext gl;
	evo_egl_context *egl; /* off screen: the context, of size ow x oh */
	int ow, oh;
	int w, h;      /* the last frame's */
	uint8_t *shot; /* the last frame's pixels, rows bottom first */
	size_t shot_cap;
	evo_raster panel;
	/* the camera: what it orbits, from where */
	double target[3];
	double yaw, pitch, dist; /* radians; metres */
	int has_target;
	int aimed; /* first_view done */
	int drag;  /* 1: orbit (left), 2: pan (right) */
	char title[128];
};

/* Panel width as the 2D viewer has it. */
static int panel_w(int w)
{
	return w >= 3 * EVO_VIEW_PANEL_W ? EVO_VIEW_PANEL_W : w / 3;
}

/* Mark one loaded library never to be unloaded (dl_iterate_phdr's
 * callback). */
static int pin(struct dl_phdr_info *info, size_t size, void *data)
{
	(void)size;
	(void)data;
	if (info->dlpi_name && info->dlpi_name[0]) {
		void *h = dlopen(info->dlpi_name,
				 RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE);
		if (h)
			dlclose(h); /* the pin stays: NODELETE is sticky */
	}
	return 0;
}

/* The camera as a new view has it (view3d.h). */
static void camera_start(evo_view3d *v)
{
	v->yaw = -2.4;
	v->pitch = 0.45;
	v->dist = 4;
}

/* Keep the GL driver loaded to the end of the process. */
static void pin_drivers(void)
{
	/* The GL driver Mesa loads for the context (llvmpipe, LLVM) would be
	 * unloaded with it, and the one-time allocations it never frees then
	 * show in LeakSanitizer's report under frames it cannot name, which
	 * tests/lsan.supp's library patterns cannot match. Kept loaded to the
	 * end of the process (as it is until then in any case), they keep
	 * their names. */
	dl_iterate_phdr(pin, NULL);
}

evo_view3d *evo_view3d_open(int width, int height, evo_err *err)
{
	evo_view3d *v = view_start_sdl(1, "the 3D view", &width, &height,
				       sizeof *v, err);
	if (!v)
		return NULL;
	camera_start(v);
	SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 24);
	SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
	v->window = SDL_CreateWindow("evo", SDL_WINDOWPOS_CENTERED,
				     SDL_WINDOWPOS_CENTERED, width, height,
				     SDL_WINDOW_OPENGL | SDL_WINDOW_RESIZABLE);
	if (v->window)
		v->gl = SDL_GL_CreateContext(v->window);
	if (!v->gl) {
		evo_fail(err, "cannot open the 3D view: no OpenGL: %s",
			 SDL_GetError());
		evo_view3d_close(v);
		return NULL;
	}
	SDL_GL_SetSwapInterval(0);
	pin_drivers();
	return v;
}

evo_view3d *evo_view3d_open_offscreen(int width, int height, evo_err *err)
{
	if (width <= 0 || height <= 0) {
		width = 1024;
		height = 720;
	}
	evo_view3d *v = calloc(1, sizeof *v);
	if (!v) {
		evo_fail(err, "cannot open the 3D view: out of memory");
		return NULL;
	}
	camera_start(v);
	v->ow = width;
	v->oh = height;
	v->egl = evo_egl_open(width, height, err);
	if (!v->egl) {
		free(v);
		return NULL;
	}
	pin_drivers();
	return v;
}

void evo_view3d_close(evo_view3d *v)
{
	if (!v)
		return;
	int sdl = !v->egl; /* SDL's video was started for a window */
	evo_egl_close(v->egl);
	if (v->gl)
		SDL_GL_DeleteContext(v->gl);
	if (v->window)
		SDL_DestroyWindow(v->window);
	evo_raster_free(&v->panel);
	free(v->shot);
	free(v);
	if (!sdl)
		return;
	SDL_QuitSubSystem(SDL_INIT_VIDEO);
	if (SDL_WasInit(SDL_INIT_EVERYTHING) == 0)
		SDL_Quit();
}

/* ---- shapes ---------------------------------------------------------- */

static void colour(uint32_t rgb, double alpha)
{
	glColor4d(((rgb >> 16) & 255) / 255.0, ((rgb >> 8) & 255) / 255.0,
		  (rgb & 255) / 255.0, alpha);
}

/* A box of half sides h around the origin. */
static void box(const double h[3])
{
	static const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5},
					{0, 4, 5, 1}, {2, 3, 7, 6},
					{0, 2, 6, 4}, {1, 5, 7, 3}};
	static const double normals[6][3] = {{-1, 0, 0}, {1, 0, 0},  {0, -1, 0},
					     {0, 1, 0},	 {0, 0, -1}, {0, 0, 1}};
	glBegin(GL_QUADS);
	for (int f = 0; f < 6; f++) {
		glNormal3dv(normals[f]);
		for (int k = 0; k < 4; k++) {
			int c = faces[f][k];
			glVertex3d(c & 4 ? h[0] : -h[0], c & 2 ? h[1] : -h[1],
				   c & 1 ? h[2] : -h[2]);
		}
	}
	glEnd();
}

#define SLICES 20

static void sphere(double r)
{
	for (int i = 0; i < SLICES / 2; i++) {
		double a0 = M_PI * i / (SLICES / 2) - M_PI / 2;
		double a1 = M_PI * (i + 1) / (SLICES / 2) - M_PI / 2;
		glBegin(GL_QUAD_STRIP);
		for (int j = 0; j <= SLICES; j++) {
			double b = 2 * M_PI * j / SLICES;
			double n0[3] = {cos(a0) * cos(b), cos(a0) * sin(b),
					sin(a0)};
			double n1[3] = {cos(a1) * cos(b), cos(a1) * sin(b),
					sin(a1)};
			glNormal3dv(n1);
			glVertex3d(r * n1[0], r * n1[1], r * n1[2]);
			glNormal3dv(n0);
			glVertex3d(r * n0[0], r * n0[1], r * n0[2]);
		}
		glEnd();
	}
}

/* A cylinder along z, radius r, half length hl, with its caps. */
static void cylinder(double r, double hl)
{
	glBegin(GL_QUAD_STRIP);
	for (int j = 0; j <= SLICES; j++) {
		double b = 2 * M_PI * j / SLICES;
		glNormal3d(cos(b), sin(b), 0);
		glVertex3d(r * cos(b), r * sin(b), hl);
		glVertex3d(r * cos(b), r * sin(b), -hl);
	}
	glEnd();
	for (int s = -1; s <= 1; s += 2) {
		glBegin(GL_TRIANGLE_FAN);
		glNormal3d(0, 0, s);
		glVertex3d(0, 0, s * hl);
		for (int j = 0; j <= SLICES; j++) {
			double b = 2 * M_PI * j / SLICES * -s;
			glVertex3d(r * cos(b), r * sin(b), s * hl);
		}
		glEnd();
	}
}

/* Multiply in the pose (pos, R row-major world = R body). */
static void pose(const double pos[3], const double R[9])
{
	double m[16] = {R[0], R[3], R[6], 0, R[1],   R[4],   R[7],   0,
			R[2], R[5], R[8], 0, pos[0], pos[1], pos[2], 1};
	glMultMatrixd(m);
}

/* A static shape as world3d has it: turned by yaw, a cylinder along its
 * axis. */
static void shape(const evo_shape3d *s)
{
	glPushMatrix();
	glTranslated(s->pos[0], s->pos[1], s->pos[2]);
	glRotated(s->yaw * 180 / M_PI, 0, 0, 1);
	if (s->type == EVO_SHAPE3D_BOX)
		box(s->half);
	else if (s->type == EVO_SHAPE3D_SPHERE)
		sphere(s->radius);
	else
		cylinder(s->radius, s->half_length);
	glPopMatrix();
}

/* ---- the world ---------------------------------------------------------- */

static void ground(void)
{
	glNormal3d(0, 0, 1);
	glBegin(GL_QUADS);
	for (int i = -20; i < 20; i++)
		for (int j = -20; j < 20; j++) {
			colour((i + j) & 1 ? 0xE4E1D6u : 0xD8D4C6u, 1);
			glVertex3d(i, j, 0);
			glVertex3d(i + 1, j, 0);
			glVertex3d(i + 1, j + 1, 0);
			glVertex3d(i, j + 1, 0);
		}
	glEnd();
}

/* A thing's colour: the one it was given (scene:colour), else `plain`. */
static uint32_t coloured(const evo_scene3d *sc, evo_blob_kind kind, int index,
			 uint32_t plain)
{
	int c = evo_view_colour_of(&sc->swarm, kind, index);
	return c < 0 ? plain : evo_view_blob_colour(c);
}

/* The floor patches, on the ground drawn just before: with no depth
 * test, they paint over it alone and leave its depth as it was. */
static void patches(const evo_swarm *w)
{
	glDisable(GL_DEPTH_TEST);
	glNormal3d(0, 0, 1);
	for (int i = 0; i < w->n_patches; i++) {
		const evo_patch *pa = &w->patch[i];
		colour(evo_view_grey(pa->grey), 1);
		glPushMatrix();
		glTranslated(pa->x, pa->y, 0);
		glRotated(pa->yaw * 180 / M_PI, 0, 0, 1);
		glBegin(pa->circle ? GL_TRIANGLE_FAN : GL_QUADS);
		if (pa->circle) {
			glVertex3d(0, 0, 0);
			for (int j = 0; j <= 2 * SLICES; j++) {
				double b = M_PI * j / SLICES;
				glVertex3d(pa->radius * cos(b),
					   pa->radius * sin(b), 0);
			}
		} else {
			glVertex3d(-pa->hx, -pa->hy, 0);
			glVertex3d(pa->hx, -pa->hy, 0);
			glVertex3d(pa->hx, pa->hy, 0);
			glVertex3d(-pa->hx, pa->hy, 0);
		}
		glEnd();
		glPopMatrix();
	}
	glEnable(GL_DEPTH_TEST);
}

/* The lights: spheres that shine, so not shaded. */
static void light_marks(const evo_scene3d *sc)
{
	glDisable(GL_LIGHTING);
	for (int i = 0; i < sc->swarm.n_lights; i++) {
		const evo_light *l = &sc->swarm.light[i];
		double r = 0.25 * sqrt(l->intensity);
		r = r < EVO_VIEW3D_LIGHT_MIN   ? EVO_VIEW3D_LIGHT_MIN
		    : r > EVO_VIEW3D_LIGHT_MAX ? EVO_VIEW3D_LIGHT_MAX
					       : r;
		colour(coloured(sc, EVO_BLOB_LIGHT, i, EVO_VIEW_LIGHT), 1);
		glPushMatrix();
		glTranslated(l->pos[0], l->pos[1], l->pos[2]);
		sphere(r);
		glPopMatrix();
	}
	glEnable(GL_LIGHTING);
}

static void bot(const evo_scene3d *sc, const evo_bot *b)
{
	glPushMatrix();
	pose(b->pos, b->R);
	/* a team's bot in its team's colour, as in the 2D view; a bot given
	 * a colour in that one */
	colour(coloured(sc, EVO_BLOB_BOT, (int)(b - sc->bot),
			b->def.team >= 0 ? evo_view_team_colour(b->def.team)
					 : EVO_VIEW3D_BOT),
	       1);
	if (b->def.radius > 0)
		sphere(b->def.radius);
	else
		box(b->def.half);
	/* its nose: a white block ahead */
	colour(0xFFFFFFu, 1);
	double r = b->def.radius > 0 ? b->def.radius : b->def.half[0];
	glPushMatrix();
	glTranslated(r, 0, 0);
	static const double nose[3] = {0.02, 0.04, 0.02};
	box(nose);
	glPopMatrix();
	if (b->def.caster_radius > 0) {
		colour(0x404040u, 1);
		glPushMatrix();
		glTranslated(b->def.caster_pos[0], b->def.caster_pos[1],
			     b->def.caster_pos[2]);
		sphere(b->def.caster_radius);
		glPopMatrix();
	}
	for (int k = 0; k < b->n_actuators; k++) {
		const evo_actuator *a = &b->actuator[k];
		if (a->def.kind != EVO_ACT_PROPELLER)
			continue;
		colour(0x303030u, 1);
		glPushMatrix();
		glTranslated(a->def.pos[0], a->def.pos[1], a->def.pos[2]);
		/* turn z onto its axis */
		const double *ax = a->def.axis;
		double ang = acos(ax[2] > 1 ? 1 : ax[2] < -1 ? -1 : ax[2]);
		if (fabs(ang) > 1e-9)
			glRotated(ang * 180 / M_PI, -ax[1], ax[0], 0);
		cylinder(0.08, 0.03);
		glPopMatrix();
	}
	glPopMatrix();
	/* wheels, each its own body */
	for (int k = 0; k < b->n_actuators; k++) {
		const evo_actuator *a = &b->actuator[k];
		if (a->body < 0 || !sc->world)
			continue;
		double p[3], R[9];
		evo_body3d_pose(sc->world, a->body, p, R);
		glPushMatrix();
		pose(p, R);
		glRotated(90, 1, 0, 0);
		colour(0x303030u, 1);
		cylinder(a->def.radius, a->def.half_width);
		glPopMatrix();
	}
}

/* Each proximity ray from its sensor to what it hit (red), or to its
 * range, pale, when clear. Unshaded, and opaque: every pixel of a ray is
 * one of the two colours. */
static void rays(const evo_bot *b)
{
	glLineWidth(2);
	glBegin(GL_LINES);
	for (int k = 0; k < b->n_sensors; k++) {
		const evo_sensor *s = &b->sensor[k];
		if (s->def.kind != EVO_SENSE_PROXIMITY)
			continue;
		double from[3], dir[3];
		evo_bot3d_to_world(b, s->def.pos, from);
		for (int i = 0; i < 3; i++)
			from[i] += b->pos[i];
		for (int r = 0; r < s->def.rays; r++) {
			double ray[3] = {s->ray_c[r], s->ray_s[r], s->ray_z};
			evo_bot3d_to_world(b, ray, dir);
			double len = s->ray[r] * s->def.range;
			colour(s->ray[r] < 1 ? EVO_VIEW_RAY_HIT
					     : EVO_VIEW3D_RAY_CLEAR,
			       1);
			glVertex3dv(from);
			glVertex3d(from[0] + dir[0] * len,
				   from[1] + dir[1] * len,
				   from[2] + dir[2] * len);
		}
	}
	glEnd();
}

/* Obstacle i's colour: the one its element was given (scene:colour, a
 * box, cylinder or sphere), else `plain`. */
static uint32_t obstacle_colour(const evo_scene3d *sc, int i, uint32_t plain)
{
	for (int e = 0; e < sc->n_elements; e++)
		if (sc->element[e].obstacle == i)
			return coloured(sc, EVO_BLOB_ELEMENT, e, plain);
	return plain;
}

static void world(const evo_scene3d *sc)
{
	ground();
	patches(&sc->swarm);
	for (int i = 0; i < sc->n_obstacles; i++) {
		const evo_shape3d *o = &sc->obstacle[i];
		colour(obstacle_colour(sc, i,
				       o->category == EVO_CAT3D_GROUND
					   ? EVO_VIEW3D_BUMP
					   : EVO_VIEW3D_OBSTACLE),
		       1);
		shape(o);
	}
	for (int i = 0; i < sc->n_elements; i++) {
		const evo_element *e = &sc->element[i];
		if (e->def.kind == EVO_PIECE_TARGET) {
			glPushMatrix();
			glTranslated(e->pos[0], e->pos[1], e->pos[2]);
			/* one set off shows faintly, as 2D's zones */
			colour(coloured(sc, EVO_BLOB_ELEMENT, i,
					EVO_VIEW3D_TARGET),
			       e->active ? 1 : 0.2);
			sphere(e->def.radius);
			glPopMatrix();
		} else if (e->def.kind == EVO_PIECE_OBJECT && e->active) {
			glPushMatrix();
			pose(e->pos, e->R);
			colour(coloured(sc, EVO_BLOB_ELEMENT, i,
					EVO_VIEW_OBJECT),
			       1);
			if (e->def.sphere)
				sphere(e->def.radius);
			else
				box(e->def.half);
			glPopMatrix();
		}
	}
	for (int i = 0; i < sc->n_bots; i++)
		bot(sc, &sc->bot[i]);
	light_marks(sc);
	/* translucent last: zones, then the rays */
	glDepthMask(GL_FALSE);
	for (int i = 0; i < sc->n_elements; i++) {
		const evo_element *e = &sc->element[i];
		if (e->def.kind != EVO_PIECE_ZONE)
			continue;
		glPushMatrix();
		glTranslated(e->pos[0], e->pos[1], e->pos[2]);
		glRotated(e->def.yaw * 180 / M_PI, 0, 0, 1);
		colour(coloured(sc, EVO_BLOB_ELEMENT, i, EVO_VIEW_ZONE),
		       e->active ? 0.3 : 0.1);
		box(e->def.half);
		glPopMatrix();
	}
	glDepthMask(GL_TRUE);
	glDisable(GL_LIGHTING);
	for (int i = 0; i < sc->n_bots; i++)
		rays(&sc->bot[i]);
	glEnable(GL_LIGHTING);
}

/* The camera: a perspective of 50 degrees over the world area, looking
 * from the orbit's eye at its target, z up. */
static void camera(const evo_view3d *v, int ww, int h)
{
	glMatrixMode(GL_PROJECTION);
	glLoadIdentity();
	double near = 0.05, far = 200, aspect = (double)ww / h;
	double top = near * tan(25 * M_PI / 180);
	glFrustum(-top * aspect, top * aspect, -top, top, near, far);
	glMatrixMode(GL_MODELVIEW);
	glLoadIdentity();
	double eye[3] = {v->target[0] + v->dist * cos(v->pitch) * cos(v->yaw),
			 v->target[1] + v->dist * cos(v->pitch) * sin(v->yaw),
			 v->target[2] + v->dist * sin(v->pitch)};
	/* look-at: f ahead, s to the right, u up */
	double f[3], s[3], u[3], up[3] = {0, 0, 1};
	for (int i = 0; i < 3; i++)
		f[i] = v->target[i] - eye[i];
	double n = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
	for (int i = 0; i < 3; i++)
		f[i] /= n;
	s[0] = f[1] * up[2] - f[2] * up[1];
	s[1] = f[2] * up[0] - f[0] * up[2];
	s[2] = f[0] * up[1] - f[1] * up[0];
	n = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
	for (int i = 0; i < 3; i++)
		s[i] /= n;
	u[0] = s[1] * f[2] - s[2] * f[1];
	u[1] = s[2] * f[0] - s[0] * f[2];
	u[2] = s[0] * f[1] - s[1] * f[0];
	double m[16] = {s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0,
			s[2], u[2], -f[2], 0, 0,    0,	  0,	 1};
	glMultMatrixd(m);
	glTranslated(-eye[0], -eye[1], -eye[2]);
}

static void lights(void)
{
	static const float ambient[4] = {0.45f, 0.45f, 0.45f, 1};
	static const float diffuse[4] = {0.65f, 0.65f, 0.65f, 1};
	static const float dir[4] = {0.4f, 0.3f, 1.0f, 0}; /* directional */
	glEnable(GL_LIGHTING);
	glEnable(GL_LIGHT0);
	glLightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient);
	glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
	glLightfv(GL_LIGHT0, GL_POSITION, dir);
	glEnable(GL_COLOR_MATERIAL);
	glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
	glEnable(GL_NORMALIZE);
}

/* The first frame's camera: where the scene has a target, from beyond the
 * robot, far enough back that the target shows ahead of it. */
static void first_view(evo_view3d *v, const evo_scene3d *sc)
{
	const double *b = sc->bot[0].pos;
	for (int i = 0; i < sc->n_elements; i++) {
		const evo_element *e = &sc->element[i];
		if (e->def.kind != EVO_PIECE_TARGET)
			continue;
		double dx = b[0] - e->pos[0], dy = b[1] - e->pos[1];
		double d = sqrt(dx * dx + dy * dy);
		v->yaw = atan2(dy, dx);
		v->dist = 1.5 * d + 3;
		return;
	}
}

void evo_view3d_draw(evo_view3d *v, const evo_scene3d *sc, int follow,
		     const evo_viewer_panel *p)
{
	int w = v->ow, h = v->oh;
	if (v->window)
		SDL_GL_GetDrawableSize(v->window, &w, &h);
	if (w < 2 || h < 2)
		return;
	if (v->window && p && p->title &&
	    strncmp(p->title, v->title, sizeof v->title)) {
		snprintf(v->title, sizeof v->title, "%s", p->title);
		char t[160];
		snprintf(t, sizeof t, "evo - %s", v->title);
		SDL_SetWindowTitle(v->window, t);
	}
	evo_view3d_aim(v, sc);
	if (follow >= 0 && follow < sc->n_bots) {
		memcpy(v->target, sc->bot[follow].pos, sizeof v->target);
		v->has_target = 1;
	} else if (!v->has_target && sc->n_bots > 0) {
		memcpy(v->target, sc->bot[0].pos, sizeof v->target);
		v->has_target = 1;
	}
	int pw = panel_w(w), ww = w - pw;
	glViewport(0, 0, ww, h);
	glEnable(GL_SCISSOR_TEST);
	glScissor(0, 0, w, h);
	colour(EVO_VIEW3D_SKY, 1);
	glClearColor(((EVO_VIEW3D_SKY >> 16) & 255) / 255.0f,
		     ((EVO_VIEW3D_SKY >> 8) & 255) / 255.0f,
		     (EVO_VIEW3D_SKY & 255) / 255.0f, 1);
	glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
	glDisable(GL_SCISSOR_TEST);
	glEnable(GL_DEPTH_TEST);
	glEnable(GL_BLEND);
	glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
	camera(v, ww, h);
	lights();
	world(sc);
	/* the panel, as pixels at the right (rows bottom first for GL) */
	glDisable(GL_LIGHTING);
	glDisable(GL_DEPTH_TEST);
	glDisable(GL_BLEND);
	if (pw >= 40 && (v->panel.w != pw || v->panel.h != h)) {
		evo_raster_free(&v->panel);
		evo_raster_init(&v->panel, pw, h, NULL);
	}
	if (pw >= 40 && v->panel.pixels && p) {
		evo_view_render_panel(&v->panel, 0, p);
		glViewport(0, 0, w, h);
		glMatrixMode(GL_PROJECTION);
		glLoadIdentity();
		glOrtho(0, w, 0, h, -1, 1);
		glMatrixMode(GL_MODELVIEW);
		glLoadIdentity();
		glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
		glRasterPos2i(ww, h - 1);
		glPixelZoom(1, -1);
		glDrawPixels(pw, h, GL_RGB, GL_UNSIGNED_BYTE, v->panel.pixels);
		glPixelZoom(1, 1);
	}
	/* kept for a screenshot: the frame as it is shown */
	size_t need = (size_t)w * h * 3;
	if (need > v->shot_cap) {
		free(v->shot);
		v->shot = malloc(need);
		v->shot_cap = v->shot ? need : 0;
	}
	if (v->shot) {
		glPixelStorei(GL_PACK_ALIGNMENT, 1);
		glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, v->shot);
		v->w = w;
		v->h = h;
	}
	if (v->window)
		SDL_GL_SwapWindow(v->window);
}

void evo_view3d_aim(evo_view3d *v, const evo_scene3d *sc)
{
	if (!v->aimed && sc->n_bots > 0)
		first_view(v, sc);
	v->aimed = 1;
}

int evo_view3d_frame(const evo_view3d *v, evo_raster *im)
{
	if (!v->shot || v->w != im->w || v->h != im->h)
		return -1;
	size_t row = (size_t)v->w * 3;
	for (int y = 0; y < v->h; y++) /* OpenGL's rows are bottom first */
		memcpy(im->pixels + row * y, v->shot + row * (v->h - 1 - y),
		       row);
	return 0;
}

int evo_view3d_screenshot(evo_view3d *v, const char *png_path, evo_err *err)
{
	if (!v->shot || v->w < 1)
		return evo_fail(err, "%s: no frame drawn yet", png_path);
	size_t row = (size_t)v->w * 3;
	uint8_t *px = malloc(row * v->h);
	if (!px)
		return evo_fail(err, "%s: out of memory", png_path);
	for (int y = 0; y < v->h; y++) /* OpenGL's rows are bottom first */
		memcpy(px + row * y, v->shot + row * (v->h - 1 - y), row);
	int rc = evo_png_write(png_path, px, v->w, v->h, 3, err);
	free(px);
	return rc;
}

/* ---- events -------------------------------------------------------------- */

evo_view_action evo_view3d_poll(evo_view3d *v)
{
	SDL_Event ev;
	if (!v->window)
		return EVO_VIEW_NONE;
	while (SDL_PollEvent(&ev)) {
		evo_view_action a = view_action_of(&ev);
		if (a != EVO_VIEW_NONE)
			return a;
		/* nearer or farther; no zoom to go back to */
		view_zoom z = view_zoom_of(&ev);
		if (z == VIEW_ZOOM_IN || z == VIEW_ZOOM_OUT) {
			v->dist *= z == VIEW_ZOOM_IN ? 0.8 : 1.25;
			v->dist = v->dist < 0.3	 ? 0.3
				  : v->dist > 80 ? 80
						 : v->dist;
		}
		if (z != VIEW_ZOOM_NONE || ev.type == SDL_MOUSEWHEEL)
			continue;
		if (ev.type == SDL_MOUSEBUTTONDOWN) {
			v->drag = ev.button.button == SDL_BUTTON_LEFT	 ? 1
				  : ev.button.button == SDL_BUTTON_RIGHT ? 2
									 : 0;
			continue;
		}
		if (ev.type == SDL_MOUSEBUTTONUP) {
			v->drag = 0;
			continue;
		}
		if (ev.type == SDL_MOUSEMOTION && v->drag == 1) {
			v->yaw -= ev.motion.xrel * 0.01;
			v->pitch += ev.motion.yrel * 0.01;
			v->pitch = v->pitch < 0.05   ? 0.05
				   : v->pitch > 1.55 ? 1.55
						     : v->pitch;
			continue;
		}
		if (ev.type == SDL_MOUSEMOTION && v->drag == 2) {
			/* along the ground, as the view faces */
			double k = v->dist * 0.002;
			double c = cos(v->yaw), s = sin(v->yaw);
			v->target[0] +=
			    (ev.motion.xrel * s + ev.motion.yrel * c) * k;
			v->target[1] +=
			    (-ev.motion.xrel * c + ev.motion.yrel * s) * k;
			return EVO_VIEW_FREE;
		}
	}
	return EVO_VIEW_NONE;
}
