/* The 3D world over ODE 0.16 (sim/world3d/world3d.h): the only file of
 * evo that includes ODE. */
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <ode/ode.h>
#include <ode/threading_impl.h>

#include "scene/store.h"
#include "world3d/world3d.h"

/* What evo knows of each geom, reached through dGeomGetData as index + 1
 * (a pointer into an array that grows would go stale). */
typedef struct geom_info {
	dGeomID g;
	unsigned category;
	int group;
	double friction;
} geom_info;

/* Group `group` touched the shape of geom index `geom`. */
struct touch {
	int group, geom;
};

struct evo_world3d {
	evo_world3d_def def;
	dWorldID world;
	/* The world's own stepping implementation: without one, ODE steps
	 * every world through one global built-in one, and two workers
	 * stepping their worlds at once corrupt its job list. */
	dThreadingImplementationID threading;
	dSpaceID statics; /* the ground and static shapes */
	dSpaceID moving;  /* the bodies' shapes */
	dJointGroupID contacts;
	dGeomID ray;
	int n_geoms, cap_geoms;
	geom_info *geom;
	int n_bodies, cap_bodies;
	dBodyID *body;
	int n_hinges, cap_hinges;
	dJointID *hinge;
	int n_groups; /* touching[] covers groups 0 .. n_groups - 1 */
	int *touching;
	/* which shapes each group touched since evo_world3d_forget_touches:
	 * a (group, geom index) pair once each; kept only once it has been
	 * called (keep_touches) */
	int keep_touches;
	int n_touches, cap_touches;
	struct touch *touch;
	/* the ray cast under way */
	double ray_best;
	unsigned ray_mask;
	int ray_ignore;
};

/* ---- ODE's set-up, once per process and once per thread -------------- */

/* ODE reports an LCP solver that gave up ("LCP internal error") as a
 * message and goes on; the step's result is still checked for explosion
 * by evo, so the message only clutters a learning run's output. */
static void quiet(int num, const char *msg, va_list ap)
{
	(void)num;
	(void)msg;
	(void)ap;
}

/* ODE's own assertion failures cannot be recovered from: say what ODE
 * said, then abort as its default handler would. */
static void fatal(int num, const char *msg, va_list ap)
{
	fprintf(stderr, "evo: ODE internal error %d: ", num);
	vfprintf(stderr, msg, ap);
	fputc('\n', stderr);
	abort();
}

static pthread_once_t ode_once = PTHREAD_ONCE_INIT;
static int ode_ok;

static void init_ode(void)
{
	ode_ok = dInitODE2(0) != 0;
	dSetMessageHandler(quiet);
	dSetErrorHandler(fatal);
	dSetDebugHandler(fatal);
}

/* ODE's manual: dAllocateODEDataForThread in every thread that uses ODE
 * (collision data included), after dInitODE2; the data goes with the
 * thread when it ends (automatic clean-up, dInitODE2's default). */
static _Thread_local int thread_ready;

static int ensure_thread(void)
{
	pthread_once(&ode_once, init_ode);
	if (!ode_ok)
		return -1;
	if (!thread_ready)
		thread_ready = dAllocateODEDataForThread(dAllocateMaskAll) != 0;
	return thread_ready ? 0 : -1;
}

/* ---- creating --------------------------------------------------------- */

evo_world3d_def evo_default_world3d_def(void)
{
	evo_world3d_def d = {
	    .step = 1.0 / 60.0,
	    .gravity = 9.81,
	    .erp = 0.2,
	    .cfm = 1e-6,
	    .ground_friction = 1.0,
	    .max_speed = 100.0,
	    .max_spin = 1000.0,
	};
	return d;
}

/* Room for `need` items in *p (scene/store.h's growing arrays). */
static int grow(void **p, int *cap, int need, size_t size)
{
	evo_err err;
	return evo_store_grow(p, cap, need, size, &err);
}

/* Record a geom's category, group and friction. */
static int add_info(evo_world3d *w, dGeomID g, unsigned category, int group,
		    double friction)
{
	if (grow((void **)&w->geom, &w->cap_geoms, w->n_geoms + 1,
		 sizeof *w->geom))
		return -1;
	w->geom[w->n_geoms] = (geom_info){g, category, group, friction};
	w->n_geoms++;
	dGeomSetData(g, (void *)(intptr_t)w->n_geoms);
	return 0;
}

static const geom_info *info_of(const evo_world3d *w, dGeomID g)
{
	intptr_t k = (intptr_t)dGeomGetData(g);
	return k >= 1 && k <= w->n_geoms ? &w->geom[k - 1] : NULL;
}

evo_world3d *evo_world3d_create(const evo_world3d_def *def)
{
	if (!(def->step > 0) || !(def->max_speed > 0) || !(def->max_spin > 0) ||
	    !isfinite(def->gravity) || ensure_thread())
		return NULL;
	evo_world3d *w = calloc(1, sizeof *w);
	if (!w)
		return NULL;
	w->def = *def;
	w->world = dWorldCreate();
	w->threading = dThreadingAllocateSelfThreadedImplementation();
	if (!w->threading) {
		dWorldDestroy(w->world);
		free(w);
		return NULL;
	}
	dWorldSetStepThreadingImplementation(
	    w->world, dThreadingImplementationGetFunctions(w->threading),
	    w->threading);
	w->statics = dHashSpaceCreate(0);
	w->moving = dSimpleSpaceCreate(0);
	w->contacts = dJointGroupCreate(0);
	w->ray = dCreateRay(0, 1.0);
	dWorldSetGravity(w->world, 0, 0, -def->gravity);
	dWorldSetERP(w->world, def->erp);
	dWorldSetCFM(w->world, def->cfm);
	dWorldSetAutoDisableFlag(w->world, 0);
	dGeomID ground = dCreatePlane(w->statics, 0, 0, 1, 0);
	if (add_info(w, ground, EVO_CAT3D_GROUND, -1, def->ground_friction)) {
		evo_world3d_destroy(w);
		return NULL;
	}
	return w;
}

void evo_world3d_destroy(evo_world3d *w)
{
	if (!w)
		return;
	ensure_thread();
	dJointGroupDestroy(w->contacts);
	dGeomDestroy(w->ray);
	/* a space destroys its geoms (cleanup mode 1, ODE's default) */
	dSpaceDestroy(w->moving);
	dSpaceDestroy(w->statics);
	dWorldDestroy(w->world);
	dThreadingFreeImplementation(w->threading);
	free(w->geom);
	free(w->body);
	free(w->hinge);
	free(w->touching);
	free(w->touch);
	free(w);
}

static int positive(double v)
{
	return isfinite(v) && v > 0;
}

/* A geom for shape s in space, not yet placed. */
static dGeomID make_geom(dSpaceID space, const evo_shape3d *s)
{
	switch (s->type) {
	case EVO_SHAPE3D_BOX:
		if (!positive(s->half[0]) || !positive(s->half[1]) ||
		    !positive(s->half[2]))
			return NULL;
		return dCreateBox(space, 2 * s->half[0], 2 * s->half[1],
				  2 * s->half[2]);
	case EVO_SHAPE3D_SPHERE:
		if (!positive(s->radius))
			return NULL;
		return dCreateSphere(space, s->radius);
	case EVO_SHAPE3D_CYLINDER:
		if (!positive(s->radius) || !positive(s->half_length) ||
		    s->axis < 0 || s->axis > 2)
			return NULL;
		return dCreateCylinder(space, s->radius, 2 * s->half_length);
	}
	return NULL;
}

/* ODE's cylinders lie along their own z: turn one onto x or y. */
static void cylinder_axis(int axis, dMatrix3 R)
{
	if (axis == 0)
		dRFromAxisAndAngle(R, 0, 1, 0, M_PI / 2);
	else if (axis == 1)
		dRFromAxisAndAngle(R, 1, 0, 0, M_PI / 2);
	else
		dRSetIdentity(R);
}

int evo_world3d_add_static(evo_world3d *w, const evo_shape3d *s)
{
	if (ensure_thread() || !isfinite(s->pos[0]) || !isfinite(s->pos[1]) ||
	    !isfinite(s->pos[2]) || !isfinite(s->yaw))
		return -1;
	dGeomID g = make_geom(w->statics, s);
	if (!g)
		return -1;
	dMatrix3 turn, axis, R;
	dRFromAxisAndAngle(turn, 0, 0, 1, s->yaw);
	cylinder_axis(s->type == EVO_SHAPE3D_CYLINDER ? s->axis : 2, axis);
	dMultiply0_333(R, turn, axis);
	dGeomSetRotation(g, R);
	dGeomSetPosition(g, s->pos[0], s->pos[1], s->pos[2]);
	if (add_info(w, g, s->category, -1, s->friction)) {
		dGeomDestroy(g);
		return -1;
	}
	return w->n_geoms - 1;
}

/* The mass of a body of the given total, shaped as shape s. */
static void shape_mass(const evo_shape3d *s, double total, dMass *m)
{
	switch (s->type) {
	case EVO_SHAPE3D_BOX:
		dMassSetBoxTotal(m, total, 2 * s->half[0], 2 * s->half[1],
				 2 * s->half[2]);
		break;
	case EVO_SHAPE3D_SPHERE:
		dMassSetSphereTotal(m, total, s->radius);
		break;
	case EVO_SHAPE3D_CYLINDER:
		dMassSetCylinderTotal(m, total, s->axis + 1, s->radius,
				      2 * s->half_length);
		break;
	}
}

int evo_world3d_add_body(evo_world3d *w, const evo_body3d_def *d)
{
	if (ensure_thread() || d->n_shapes < 1 ||
	    d->n_shapes > EVO_BODY3D_MAX_SHAPES || !positive(d->mass))
		return -1;
	for (int i = 0; i < 3; i++)
		if (!isfinite(d->pos[i]))
			return -1;
	if (grow((void **)&w->body, &w->cap_bodies, w->n_bodies + 1,
		 sizeof *w->body))
		return -1;
	int group = d->group;
	if (group >= 0 && group >= w->n_groups) {
		int *t = realloc(w->touching, (size_t)(group + 1) * sizeof *t);
		if (!t)
			return -1;
		for (int i = w->n_groups; i <= group; i++)
			t[i] = 0;
		w->touching = t;
		w->n_groups = group + 1;
	}
	dGeomID g[EVO_BODY3D_MAX_SHAPES];
	for (int i = 0; i < d->n_shapes; i++) {
		g[i] = make_geom(w->moving, &d->shape[i]);
		if (!g[i]) {
			while (i-- > 0)
				dGeomDestroy(g[i]);
			return -1;
		}
	}
	dBodyID b = dBodyCreate(w->world);
	dMass m;
	shape_mass(&d->shape[0], d->mass, &m);
	dBodySetMass(b, &m);
	dMatrix3 R;
	dRFromAxisAndAngle(R, 0, 0, 1, d->yaw);
	dBodySetPosition(b, d->pos[0], d->pos[1], d->pos[2]);
	dBodySetRotation(b, R);
	for (int i = 0; i < d->n_shapes; i++) {
		const evo_shape3d *s = &d->shape[i];
		dGeomSetBody(g[i], b);
		dGeomSetOffsetPosition(g[i], s->pos[0], s->pos[1], s->pos[2]);
		if (s->type == EVO_SHAPE3D_CYLINDER) {
			dMatrix3 A;
			cylinder_axis(s->axis, A);
			dGeomSetOffsetRotation(g[i], A);
		}
		if (add_info(w, g[i], s->category, group, s->friction))
			return -1; /* the geoms go with the world */
	}
	w->body[w->n_bodies] = b;
	return w->n_bodies++;
}

int evo_world3d_add_hinge(evo_world3d *w, int a, int b, const double anchor[3],
			  const double axis[3])
{
	if (a < 0 || a >= w->n_bodies || b < 0 || b >= w->n_bodies ||
	    grow((void **)&w->hinge, &w->cap_hinges, w->n_hinges + 1,
		 sizeof *w->hinge))
		return -1;
	dJointID j = dJointCreateHinge(w->world, 0);
	dJointAttach(j, w->body[a], w->body[b]);
	dJointSetHingeAnchor(j, anchor[0], anchor[1], anchor[2]);
	dJointSetHingeAxis(j, axis[0], axis[1], axis[2]);
	w->hinge[w->n_hinges] = j;
	return w->n_hinges++;
}

void evo_world3d_hinge_torque(evo_world3d *w, int h, double torque)
{
	dJointSetHingeParam(w->hinge[h], dParamFMax, 0);
	dJointAddHingeTorque(w->hinge[h], torque);
}

void evo_world3d_hinge_velocity(evo_world3d *w, int h, double rate, double fmax)
{
	dJointSetHingeParam(w->hinge[h], dParamVel, rate);
	dJointSetHingeParam(w->hinge[h], dParamFMax, fmax);
}

double evo_world3d_hinge_rate(const evo_world3d *w, int h)
{
	return dJointGetHingeAngleRate(w->hinge[h]);
}

/* ---- bodies ------------------------------------------------------------ */

void evo_body3d_pose(const evo_world3d *w, int i, double pos[3], double R[9])
{
	const dReal *p = dBodyGetPosition(w->body[i]);
	const dReal *r = dBodyGetRotation(w->body[i]); /* 3 x 4, row-major */
	for (int k = 0; k < 3; k++) {
		pos[k] = p[k];
		R[3 * k + 0] = r[4 * k + 0];
		R[3 * k + 1] = r[4 * k + 1];
		R[3 * k + 2] = r[4 * k + 2];
	}
}

void evo_body3d_velocity(const evo_world3d *w, int i, double v[3],
			 double omega[3])
{
	const dReal *l = dBodyGetLinearVel(w->body[i]);
	const dReal *a = dBodyGetAngularVel(w->body[i]);
	for (int k = 0; k < 3; k++) {
		v[k] = l[k];
		omega[k] = a[k];
	}
}

void evo_body3d_set_velocity(evo_world3d *w, int i, const double v[3],
			     const double omega[3])
{
	dBodySetLinearVel(w->body[i], v[0], v[1], v[2]);
	dBodySetAngularVel(w->body[i], omega[0], omega[1], omega[2]);
}

void evo_body3d_set_position(evo_world3d *w, int i, const double pos[3])
{
	dBodySetPosition(w->body[i], pos[0], pos[1], pos[2]);
}

void evo_body3d_set_enabled(evo_world3d *w, int i, int enabled)
{
	dBodyID b = w->body[i];
	for (dGeomID g = dBodyGetFirstGeom(b); g; g = dBodyGetNextGeom(g)) {
		if (enabled)
			dGeomEnable(g);
		else
			dGeomDisable(g);
	}
	if (enabled) {
		dBodyEnable(b);
		return;
	}
	dBodySetLinearVel(b, 0, 0, 0);
	dBodySetAngularVel(b, 0, 0, 0);
	dBodyDisable(b);
}

double evo_body3d_mass(const evo_world3d *w, int i)
{
	dMass m;
	dBodyGetMass(w->body[i], &m);
	return m.mass;
}

void evo_body3d_add_force_at(evo_world3d *w, int i, const double f[3],
			     const double at[3])
{
	dBodyAddForceAtRelPos(w->body[i], f[0], f[1], f[2], at[0], at[1],
			      at[2]);
}

void evo_body3d_add_rel_force_at(evo_world3d *w, int i, const double f[3],
				 const double at[3])
{
	dBodyAddRelForceAtRelPos(w->body[i], f[0], f[1], f[2], at[0], at[1],
				 at[2]);
}

void evo_body3d_add_torque(evo_world3d *w, int i, const double t[3])
{
	dBodyAddTorque(w->body[i], t[0], t[1], t[2]);
}

void evo_body3d_add_force_at_pos(evo_world3d *w, int i, const double f[3],
				 const double at[3])
{
	dBodyAddForceAtPos(w->body[i], f[0], f[1], f[2], at[0], at[1], at[2]);
}

void evo_body3d_add_rel_force_at_pos(evo_world3d *w, int i, const double f[3],
				     const double at[3])
{
	dBodyAddRelForceAtPos(w->body[i], f[0], f[1], f[2], at[0], at[1],
			      at[2]);
}

void evo_body3d_set_pose(evo_world3d *w, int i, const double pos[3], double yaw)
{
	dMatrix3 R;
	dRFromAxisAndAngle(R, 0, 0, 1, yaw);
	dBodySetPosition(w->body[i], pos[0], pos[1], pos[2]);
	dBodySetRotation(w->body[i], R);
}

int evo_body3d_group(const evo_world3d *w, int i)
{
	dGeomID g = dBodyGetFirstGeom(w->body[i]);
	const geom_info *info = g ? info_of(w, g) : NULL;
	return info ? info->group : -1;
}

int evo_world3d_n_bodies(const evo_world3d *w)
{
	return w->n_bodies;
}

/* ---- the step ---------------------------------------------------------- */

#define MAX_CONTACTS 4

/* Friction of a contact: the geometric mean, 0 when either slides. */
static double mix_friction(double a, double b)
{
	return a <= 0 || b <= 0 ? 0 : sqrt(a * b);
}

/* Group g touched geom k: kept once. Should memory run out, the pair is
 * not kept, and NextOnCollisionWithTarget misses that touch. */
static void remember_touch(evo_world3d *w, int g, int k)
{
	if (!w->keep_touches)
		return;
	for (int i = 0; i < w->n_touches; i++)
		if (w->touch[i].group == g && w->touch[i].geom == k)
			return;
	if (grow((void **)&w->touch, &w->cap_touches, w->n_touches + 1,
		 sizeof *w->touch))
		return;
	w->touch[w->n_touches++] = (struct touch){g, k};
}

static void near(void *data, dGeomID g1, dGeomID g2)
{
	evo_world3d *w = data;
	const geom_info *a = info_of(w, g1), *b = info_of(w, g2);
	dBodyID b1 = dGeomGetBody(g1), b2 = dGeomGetBody(g2);
	if (!a || !b || (!b1 && !b2))
		return;
	if (a->group >= 0 && a->group == b->group)
		return;
	if (b1 && b2 && dAreConnectedExcluding(b1, b2, dJointTypeContact))
		return;
	dContact c[MAX_CONTACTS];
	memset(c, 0, sizeof c);
	int n = dCollide(g1, g2, MAX_CONTACTS, &c[0].geom, sizeof c[0]);
	if (n <= 0)
		return;
	double mu = mix_friction(a->friction, b->friction);
	for (int i = 0; i < n; i++) {
		c[i].surface.mode = dContactApprox1;
		c[i].surface.mu = mu;
		dJointID j = dJointCreateContact(w->world, w->contacts, &c[i]);
		dJointAttach(j, b1, b2);
	}
	int ground = (a->category | b->category) & EVO_CAT3D_GROUND;
	if (ground)
		return;
	if (a->group >= 0 && a->group < w->n_groups) {
		w->touching[a->group] += n;
		remember_touch(w, a->group, (int)(b - w->geom));
	}
	if (b->group >= 0 && b->group < w->n_groups) {
		w->touching[b->group] += n;
		remember_touch(w, b->group, (int)(a - w->geom));
	}
}

/* 1 when body b has blown up, with f's kind and value set. */
static int exploded(const evo_world3d *w, dBodyID b, evo_bfault *f)
{
	const dReal *p = dBodyGetPosition(b), *v = dBodyGetLinearVel(b),
		    *a = dBodyGetAngularVel(b), *q = dBodyGetQuaternion(b);
	for (int k = 0; k < 3; k++)
		if (!isfinite(p[k]) || !isfinite(v[k]) || !isfinite(a[k]) ||
		    !isfinite(q[k]) || !isfinite(q[3])) {
			f->kind = EVO_BFAULT_NAN;
			f->value = NAN;
			return 1;
		}
	double s = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	double spin = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
	if (s > w->def.max_speed) {
		f->kind = EVO_BFAULT_SPEED;
		f->value = s;
		return 1;
	}
	if (spin > w->def.max_spin) {
		f->kind = EVO_BFAULT_SPIN;
		f->value = spin;
		return 1;
	}
	return 0;
}

int evo_world3d_step(evo_world3d *w, evo_bfault *fault)
{
	if (ensure_thread())
		return -1;
	/* A body already broken (a test, or a force that was not a number)
	 * never reaches ODE's solver, which may abort on it. */
	for (int i = 0; i < w->n_bodies; i++)
		if (exploded(w, w->body[i], fault)) {
			fault->body = (evo_body_id){i, 0};
			return -1;
		}
	for (int i = 0; i < w->n_groups; i++)
		w->touching[i] = 0;
	dSpaceCollide(w->moving, w, near);
	dSpaceCollide2((dGeomID)w->moving, (dGeomID)w->statics, w, near);
	dWorldStep(w->world, w->def.step);
	dJointGroupEmpty(w->contacts);
	for (int i = 0; i < w->n_bodies; i++)
		if (exploded(w, w->body[i], fault)) {
			fault->body = (evo_body_id){i, 0};
			return -1;
		}
	return 0;
}

int evo_world3d_group_touching(const evo_world3d *w, int group)
{
	return group >= 0 && group < w->n_groups ? w->touching[group] : 0;
}

void evo_world3d_forget_touches(evo_world3d *w)
{
	w->keep_touches = 1;
	w->n_touches = 0;
}

int evo_world3d_group_touched(const evo_world3d *w, int group, int geom)
{
	for (int i = 0; i < w->n_touches; i++)
		if (w->touch[i].group == group && w->touch[i].geom == geom)
			return 1;
	return 0;
}

int evo_world3d_group_touched_body(const evo_world3d *w, int group, int body)
{
	if (body < 0 || body >= w->n_bodies)
		return 0;
	for (int i = 0; i < w->n_touches; i++)
		if (w->touch[i].group == group &&
		    dGeomGetBody(w->geom[w->touch[i].geom].g) == w->body[body])
			return 1;
	return 0;
}

/* ---- rays --------------------------------------------------------------- */

static void ray_near(void *data, dGeomID g1, dGeomID g2)
{
	evo_world3d *w = data;
	dGeomID other = g1 == w->ray ? g2 : g1;
	if (dGeomIsSpace(other)) {
		dSpaceCollide2(w->ray, other, data, ray_near);
		return;
	}
	const geom_info *in = info_of(w, other);
	if (!in || !(in->category & w->ray_mask) ||
	    (w->ray_ignore >= 0 && in->group == w->ray_ignore))
		return;
	dContactGeom c;
	if (dCollide(w->ray, other, 1, &c, sizeof c) > 0 &&
	    c.depth < w->ray_best)
		w->ray_best = c.depth;
}

double evo_world3d_raycast(evo_world3d *w, const double from[3],
			   const double dir[3], double len, unsigned mask,
			   int ignore_group)
{
	if (ensure_thread() || !(len > 0))
		return -1;
	dGeomRaySetLength(w->ray, len);
	dGeomRaySet(w->ray, from[0], from[1], from[2], dir[0], dir[1], dir[2]);
	/* the nearest hit of each geom, not the first ODE finds */
	dGeomRaySetFirstContact(w->ray, 0);
	dGeomRaySetBackfaceCull(w->ray, 0);
	dGeomRaySetClosestHit(w->ray, 1);
	w->ray_best = INFINITY;
	w->ray_mask = mask;
	w->ray_ignore = ignore_group;
	dSpaceCollide2(w->ray, (dGeomID)w->statics, w, ray_near);
	dSpaceCollide2(w->ray, (dGeomID)w->moving, w, ray_near);
	return w->ray_best <= len ? w->ray_best : -1;
}
