// The 2D world over Box2D 2.4: the only C++ in evo (sim/world2d/world.h).
#include "world2d/world.h"

#include <box2d/box2d.h>
#include <box2d/b2_distance.h>

#include <cmath>
#include <new>
#include <cstdint>
#include <vector>

namespace {

struct Slot {
	b2Body *body = nullptr;
	uint16_t generation = 0;
	evo_body_def def{}; // as added, to make the body again
	bool enabled = true; // evo_world_reset's note of it
};

} // namespace

struct evo_world {
	b2World world{b2Vec2(0.0f, 0.0f)};
	std::vector<b2Joint *> joints; // welds by id; nullptr once removed
	evo_world_def def;
	std::vector<Slot> slots;
	std::vector<int32_t> free_slots;
	b2Body *obstacles = nullptr; // one static body for every obstacle
	int n_obstacles = 0;
};

// Fixture user data holds the owning body's slot index + 1, or for an
// obstacle minus (its index + 1).
static uintptr_t slot_tag(int32_t index)
{
	return (uintptr_t)index + 1;
}

static uintptr_t obstacle_tag(int index)
{
	return (uintptr_t)(-(intptr_t)index - 1);
}

static int obstacle_of_fixture(b2Fixture *f)
{
	intptr_t tag = (intptr_t)f->GetUserData().pointer;
	return tag < 0 ? (int)(-tag - 1) : -1;
}

static b2Body *lookup(const evo_world *w, evo_body_id id)
{
	if (id.index < 0 || (size_t)id.index >= w->slots.size())
		return nullptr;
	const Slot &s = w->slots[(size_t)id.index];
	return s.generation == id.generation ? s.body : nullptr;
}

static evo_body_id id_of_fixture(const evo_world *w, b2Fixture *f)
{
	intptr_t tag = (intptr_t)f->GetUserData().pointer;
	if (tag <= 0)
		return EVO_BODY_NONE;
	int32_t index = (int32_t)(tag - 1);
	return evo_body_id{index, w->slots[(size_t)index].generation};
}

static void fill_fixture(b2FixtureDef *fd, const evo_body_def *d,
			 uintptr_t tag)
{
	fd->density = (float)d->density;
	fd->friction = (float)d->friction;
	fd->restitution = (float)d->restitution;
	fd->filter.categoryBits = d->category;
	fd->filter.maskBits = d->mask;
	fd->userData.pointer = tag;
}

/* A body of the world from its definition, tagged with its slot. */
static b2Body *make_body(evo_world *w, const evo_body_def *d, int32_t index)
{
	b2BodyDef bd;
	bd.type = !d->dynamic	 ? b2_staticBody
		  : d->kinematic ? b2_kinematicBody
				 : b2_dynamicBody;
	bd.position.Set((float)d->x, (float)d->y);
	bd.angle = (float)d->angle;
	bd.linearDamping = (float)d->linear_damping;
	bd.angularDamping = (float)d->angular_damping;
	bd.allowSleep = d->allow_sleep != 0;
	b2Body *body = w->world.CreateBody(&bd);
	b2FixtureDef fd;
	fill_fixture(&fd, d, slot_tag(index));
	b2CircleShape circle;
	b2PolygonShape box;
	if (d->shape == EVO_SHAPE_CIRCLE) {
		circle.m_radius = (float)d->radius;
		fd.shape = &circle;
	} else {
		box.SetAsBox((float)d->half_w, (float)d->half_h);
		fd.shape = &box;
	}
	body->CreateFixture(&fd);
	return body;
}

extern "C" {

evo_body_def evo_default_body_def(void) noexcept
{
	evo_body_def d = {};
	d.shape = EVO_SHAPE_CIRCLE;
	d.radius = 1.0;
	d.half_w = d.half_h = 1.0;
	d.density = 1.0;
	d.allow_sleep = 1;
	d.category = EVO_CAT_OBSTACLE;
	d.mask = EVO_CAT_ALL;
	return d;
}

evo_world_def evo_default_world_def(void) noexcept
{
	evo_world_def d;
	d.step = 1.0 / 30.0;
	d.velocity_iterations = 8;
	d.position_iterations = 3;
	return d;
}

evo_world *evo_world_create(const evo_world_def *def) noexcept
{
	evo_world *w = new (std::nothrow) evo_world;
	if (!w)
		return nullptr;
	w->def = def ? *def : evo_default_world_def();
	b2BodyDef bd;
	bd.type = b2_staticBody;
	w->obstacles = w->world.CreateBody(&bd);
	return w;
}

void evo_world_destroy(evo_world *w) noexcept
{
	delete w;
}

void evo_world_reset(evo_world *w) noexcept
{
	// Box2D's state beyond the bodies' poses and speeds (contacts and
	// their warm-starting impulses, the order of its contact and body
	// lists, its broad phase's tree) depends on everything the world
	// went through. A world made again, with the bodies added in the
	// order of their ids, is the same whatever came before.
	for (Slot &s : w->slots)
		if (s.body)
			s.enabled = s.body->IsEnabled();
	for (b2Joint *&j : w->joints)
		j = nullptr;
	w->world.~b2World();
	new (&w->world) b2World(b2Vec2(0.0f, 0.0f));
	b2BodyDef bd;
	bd.type = b2_staticBody;
	w->obstacles = w->world.CreateBody(&bd);
	w->n_obstacles = 0;
	for (size_t i = 0; i < w->slots.size(); i++) {
		Slot &s = w->slots[i];
		if (!s.body)
			continue;
		s.body = make_body(w, &s.def, (int32_t)i);
		if (!s.enabled)
			s.body->SetEnabled(false);
	}
}

void evo_world_step(evo_world *w) noexcept
{
	w->world.Step((float)w->def.step, w->def.velocity_iterations,
		      w->def.position_iterations);
}


evo_body_id evo_world_add_body(evo_world *w, const evo_body_def *d) noexcept
{
	if (d->shape == EVO_SHAPE_CIRCLE ? !(d->radius > 0)
					 : !(d->half_w > 0 && d->half_h > 0))
		return EVO_BODY_NONE;
	int32_t index;
	if (!w->free_slots.empty()) {
		index = w->free_slots.back();
		w->free_slots.pop_back();
	} else {
		// The vectors grow here, the only place they can throw; a
		// body's removal then pushes onto free_slots within the
		// capacity reserved now, so it cannot throw.
		try {
			w->free_slots.reserve(w->slots.size() + 1);
			w->slots.push_back(Slot{});
		} catch (...) { // std::bad_alloc, std::length_error
			return EVO_BODY_NONE;
		}
		index = (int32_t)w->slots.size() - 1;
	}
	Slot &s = w->slots[(size_t)index];
	s.def = *d;
	s.body = make_body(w, d, index);
	return evo_body_id{index, s.generation};
}


int evo_world_remove_body(evo_world *w, evo_body_id id) noexcept
{
	b2Body *b = lookup(w, id);
	if (!b)
		return -1;
	// Box2D destroys the body's joints with it: forget them first.
	for (b2Joint *&j : w->joints)
		if (j && (j->GetBodyA() == b || j->GetBodyB() == b))
			j = nullptr;
	w->world.DestroyBody(b);
	Slot &s = w->slots[(size_t)id.index];
	s.body = nullptr;
	s.generation++;
	w->free_slots.push_back(id.index);
	return 0;
}

int evo_body_valid(const evo_world *w, evo_body_id id) noexcept
{
	return lookup(w, id) != nullptr;
}

static int add_obstacle(evo_world *w, b2Shape *shape, double friction = 0)
{
	b2FixtureDef fd;
	evo_body_def d = evo_default_body_def();
	d.friction = friction;
	fill_fixture(&fd, &d, obstacle_tag(w->n_obstacles));
	fd.shape = shape;
	w->obstacles->CreateFixture(&fd);
	return w->n_obstacles++;
}

int evo_world_add_static_circle(evo_world *w, double x, double y,
				double r) noexcept
{
	if (!(r > 0))
		return -1;
	b2CircleShape c;
	c.m_p.Set((float)x, (float)y);
	c.m_radius = (float)r;
	return add_obstacle(w, &c);
}

int evo_world_add_static_box(evo_world *w, double x, double y, double half_w,
			     double half_h, double angle) noexcept
{
	if (!(half_w > 0 && half_h > 0))
		return -1;
	b2PolygonShape p;
	p.SetAsBox((float)half_w, (float)half_h, b2Vec2((float)x, (float)y),
		   (float)angle);
	return add_obstacle(w, &p);
}

int evo_world_add_static_segment(evo_world *w, double x1, double y1,
				 double x2, double y2) noexcept
{
	b2Vec2 a((float)x1, (float)y1), b((float)x2, (float)y2);
	if (!(b2DistanceSquared(a, b) > b2_linearSlop * b2_linearSlop))
		return -1;
	b2EdgeShape e;
	e.SetTwoSided(a, b);
	/* Friction 1: a bot with friction of its own (the mazes' robots)
	 * that drives into a wall stops there instead of sliding along it,
	 * as the papers' robots stop; Box2D mixes the two as sqrt(f1 f2), so
	 * a bot without friction slides as along any obstacle. */
	return add_obstacle(w, &e, 1.0);
}

evo_pose evo_body_pose(const evo_world *w, evo_body_id id) noexcept
{
	const b2Body *b = lookup(w, id);
	if (!b)
		return evo_pose{0, 0, 0};
	return evo_pose{b->GetPosition().x, b->GetPosition().y,
			b->GetAngle()};
}

void evo_body_set_pose(evo_world *w, evo_body_id id, evo_pose p) noexcept
{
	b2Body *b = lookup(w, id);
	if (b)
		b->SetTransform(b2Vec2((float)p.x, (float)p.y),
				(float)p.angle);
}

void evo_body_velocity(const evo_world *w, evo_body_id id, double *vx,
		       double *vy, double *omega) noexcept
{
	const b2Body *b = lookup(w, id);
	*vx = b ? b->GetLinearVelocity().x : 0;
	*vy = b ? b->GetLinearVelocity().y : 0;
	*omega = b ? b->GetAngularVelocity() : 0;
}

void evo_body_set_velocity(evo_world *w, evo_body_id id, double vx, double vy,
			   double omega) noexcept
{
	b2Body *b = lookup(w, id);
	if (!b)
		return;
	b->SetLinearVelocity(b2Vec2((float)vx, (float)vy));
	b->SetAngularVelocity((float)omega);
}

void evo_body_apply_force(evo_world *w, evo_body_id id, double fx, double fy,
			  double px, double py) noexcept
{
	b2Body *b = lookup(w, id);
	if (b)
		b->ApplyForce(b2Vec2((float)fx, (float)fy),
			      b2Vec2((float)px, (float)py), true);
}

void evo_body_apply_torque(evo_world *w, evo_body_id id, double torque) noexcept
{
	b2Body *b = lookup(w, id);
	if (b)
		b->ApplyTorque((float)torque, true);
}

int evo_body_touching(const evo_world *w, evo_body_id id) noexcept
{
	const b2Body *b = lookup(w, id);
	int n = 0;
	for (const b2ContactEdge *e = b ? b->GetContactList() : nullptr; e;
	     e = e->next)
		n += e->contact->IsTouching() ? 1 : 0;
	return n;
}

int evo_body_touching_body(const evo_world *w, evo_body_id id,
			   evo_body_id other) noexcept
{
	const b2Body *b = lookup(w, id), *o = lookup(w, other);
	for (const b2ContactEdge *e = b && o ? b->GetContactList() : nullptr;
	     e; e = e->next)
		if (e->other == o && e->contact->IsTouching())
			return 1;
	return 0;
}

int evo_body_touching_obstacle(const evo_world *w, evo_body_id id,
			       int obstacle) noexcept
{
	const b2Body *b = lookup(w, id);
	for (const b2ContactEdge *e = b ? b->GetContactList() : nullptr; e;
	     e = e->next) {
		b2Contact *c = e->contact;
		if (!c->IsTouching())
			continue;
		if (obstacle_of_fixture(c->GetFixtureA()) == obstacle ||
		    obstacle_of_fixture(c->GetFixtureB()) == obstacle)
			return 1;
	}
	return 0;
}

void evo_world_clear_obstacles(evo_world *w) noexcept
{
	w->world.DestroyBody(w->obstacles);
	b2BodyDef bd;
	bd.type = b2_staticBody;
	w->obstacles = w->world.CreateBody(&bd);
	w->n_obstacles = 0;
}

void evo_body_set_enabled(evo_world *w, evo_body_id id, int enabled) noexcept
{
	b2Body *b = lookup(w, id);
	if (b)
		b->SetEnabled(enabled != 0);
}

void evo_body_wake(evo_world *w, evo_body_id id) noexcept
{
	b2Body *b = lookup(w, id);
	if (b)
		b->SetAwake(true);
}

int evo_world_weld(evo_world *w, evo_body_id a, evo_body_id b) noexcept
{
	b2Body *ba = lookup(w, a), *bb = lookup(w, b);
	if (!ba || !bb || ba == bb)
		return -1;
	// Room for the joint first, so that no joint exists without an id.
	try {
		w->joints.push_back(nullptr);
	} catch (...) { // std::bad_alloc, std::length_error
		return -1;
	}
	b2WeldJointDef jd;
	jd.Initialize(ba, bb, bb->GetPosition());
	jd.collideConnected = false;
	w->joints.back() = w->world.CreateJoint(&jd);
	return (int)w->joints.size() - 1;
}

void evo_world_unweld(evo_world *w, int joint) noexcept
{
	if (joint < 0 || (size_t)joint >= w->joints.size() ||
	    !w->joints[(size_t)joint])
		return;
	w->world.DestroyJoint(w->joints[(size_t)joint]);
	w->joints[(size_t)joint] = nullptr;
}

namespace {

struct NearestHit : b2RayCastCallback {
	const evo_world *w;
	uint16_t mask;
	evo_body_id ignore;
	float fraction = -1.0f;
	float ReportFixture(b2Fixture *f, const b2Vec2 &, const b2Vec2 &,
			    float frac) override
	{
		if (!(f->GetFilterData().categoryBits & mask))
			return -1.0f; // skip this fixture, go on
		evo_body_id id = id_of_fixture(w, f);
		if (id.index >= 0 && id.index == ignore.index)
			return -1.0f;
		fraction = frac;
		return frac; // clip the ray: only nearer hits from now on
	}
};

// evo_world_body_blocked's test of each shape near the body: a circle is
// blocked by a shape closer to its centre than its radius (Box2D's
// distance between the centre and the shape's core, its skin left out,
// as Lehman's maze simulator measures a wall's distance to the robot); a
// box by any overlap.
struct Blocked : b2QueryCallback {
	b2Fixture *self = nullptr;
	b2Transform xf;
	int hit = 0;
	bool ReportFixture(b2Fixture *f) override
	{
		if (f->GetBody() == self->GetBody() || f->IsSensor())
			return true;
		const b2Filter &a = self->GetFilterData();
		const b2Filter &b = f->GetFilterData();
		if (!(a.maskBits & b.categoryBits) ||
		    !(b.maskBits & a.categoryBits))
			return true;
		const b2Shape *mine = self->GetShape();
		const b2Transform &other = f->GetBody()->GetTransform();
		for (int32 k = 0; k < f->GetShape()->GetChildCount(); k++) {
			if (mine->GetType() != b2Shape::e_circle) {
				if (b2TestOverlap(mine, 0, f->GetShape(), k, xf,
						  other))
					hit = 1;
				continue;
			}
			b2DistanceInput in;
			in.proxyA.Set(mine, 0);
			in.proxyB.Set(f->GetShape(), k);
			in.transformA = xf;
			in.transformB = other;
			in.useRadii = false;
			b2SimplexCache cache;
			cache.count = 0;
			b2DistanceOutput out;
			b2Distance(&out, &cache, &in);
			const b2Shape *s = f->GetShape();
			float reach = mine->m_radius;
			if (s->GetType() == b2Shape::e_circle)
				reach += s->m_radius; // a circle's core is its centre
			if (out.distance < reach)
				hit = 1;
		}
		return hit == 0; // the first blocking shape ends the query
	}
};

struct Collect : b2QueryCallback {
	const evo_world *w;
	uint16_t mask;
	evo_shape_info *out;
	int cap, n = 0;
	bool ReportFixture(b2Fixture *f) override
	{
		if (!(f->GetFilterData().categoryBits & mask))
			return true;
		if (n < cap) {
			evo_shape_info &s = out[n];
			s = evo_shape_info{};
			s.category = f->GetFilterData().categoryBits;
			s.body = id_of_fixture(w, f);
			s.obstacle = obstacle_of_fixture(f);
			const b2Transform &xf = f->GetBody()->GetTransform();
			if (f->GetType() == b2Shape::e_circle) {
				const b2CircleShape *c =
					(const b2CircleShape *)f->GetShape();
				b2Vec2 p = b2Mul(xf, c->m_p);
				s.type = EVO_SHAPE_CIRCLE;
				s.x = p.x;
				s.y = p.y;
				s.radius = c->m_radius;
			} else if (f->GetType() == b2Shape::e_edge) {
				const b2EdgeShape *e =
					(const b2EdgeShape *)f->GetShape();
				b2Vec2 a = b2Mul(xf, e->m_vertex1);
				b2Vec2 b = b2Mul(xf, e->m_vertex2);
				s.type = EVO_SHAPE_SEGMENT;
				s.x = 0.5 * ((double)a.x + b.x);
				s.y = 0.5 * ((double)a.y + b.y);
				s.vx[0] = a.x;
				s.vy[0] = a.y;
				s.vx[1] = b.x;
				s.vy[1] = b.y;
			} else {
				const b2PolygonShape *p =
					(const b2PolygonShape *)f->GetShape();
				s.type = EVO_SHAPE_BOX;
				b2Vec2 c = b2Mul(xf, p->m_centroid);
				s.x = c.x;
				s.y = c.y;
				for (int i = 0; i < 4 && i < p->m_count; i++) {
					b2Vec2 v = b2Mul(xf, p->m_vertices[i]);
					s.vx[i] = v.x;
					s.vy[i] = v.y;
				}
			}
		}
		n++;
		return true;
	}
};

} // namespace

double evo_world_raycast(const evo_world *w, double x1, double y1, double x2,
			 double y2, uint16_t mask, evo_body_id ignore) noexcept
{
	NearestHit cb;
	cb.w = w;
	cb.mask = mask;
	cb.ignore = ignore;
	b2Vec2 a((float)x1, (float)y1), b((float)x2, (float)y2);
	if (b2DistanceSquared(a, b) < 1e-12f)
		return -1;
	w->world.RayCast(&cb, a, b);
	return cb.fraction;
}

int evo_world_body_blocked(const evo_world *w, evo_body_id id) noexcept
{
	b2Body *body = lookup(w, id);
	if (!body || !body->GetFixtureList())
		return 0;
	Blocked cb;
	cb.self = body->GetFixtureList();
	cb.xf = body->GetTransform();
	b2AABB box;
	cb.self->GetShape()->ComputeAABB(&box, cb.xf, 0);
	w->world.QueryAABB(&cb, box);
	return cb.hit;
}

int evo_world_query(const evo_world *w, double x0, double y0, double x1,
		    double y1, uint16_t mask, evo_shape_info *out,
		    int cap) noexcept
{
	Collect cb;
	cb.w = w;
	cb.mask = mask;
	cb.out = out;
	cb.cap = cap;
	b2AABB box;
	box.lowerBound.Set((float)x0, (float)y0);
	box.upperBound.Set((float)x1, (float)y1);
	w->world.QueryAABB(&cb, box);
	return cb.n;
}

} // extern "C"

// Box2D times the phases of every b2World::Step for b2World::GetProfile,
// each with a b2Timer that reads the clock (gettimeofday) when it starts
// and when it is read: a dozen clock reads a step, an island more. evo
// never reads the profile, and in a small world (a maze robot, a few
// walls) those reads were a sixth of an episode's time. These two
// definitions take the place of the library's (the shared library's own
// calls go to the program's definitions first, as with any symbol of a
// shared library): the timers do nothing and read 0. The simulation is
// the same to the bit; only GetProfile's figures become 0.
void b2Timer::Reset() {}

float b2Timer::GetMilliseconds() const
{
	return 0.0f;
}
