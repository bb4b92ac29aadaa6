// The 2D world when memory runs out (sim/world2d/world_box2d.cpp): its C
// entry points are noexcept and turn std::bad_alloc into the failure value
// world.h documents, so a C caller (scene.c, actuators.c) sees
// EVO_BODY_NONE, -1 or NULL, never an exception unwinding through its
// frames; and the world goes on working once memory is back.
//
// Box2D allocates with malloc (b2Alloc); only evo's own std::vector
// growth and the world itself go through operator new, which this test
// replaces with one that throws std::bad_alloc while `fail_new` is set.
// The replacement also serves the nothrow form (as the C++ library's
// does, it returns nullptr where the plain form throws), so that under
// AddressSanitizer, whose own operator new would otherwise serve it, the
// test sees the same thing.
#include <cstdio>
#include <cstdlib>
#include <new>

#include "harness.h"
#include "world2d/world.h"

static bool fail_new;
static int refused_news;

void *operator new(std::size_t n)
{
	if (fail_new) {
		refused_news++;
		throw std::bad_alloc();
	}
	if (void *p = std::malloc(n ? n : 1))
		return p;
	throw std::bad_alloc();
}

void *operator new(std::size_t n, const std::nothrow_t &) noexcept
{
	try {
		return ::operator new(n);
	} catch (...) {
		return nullptr;
	}
}

void operator delete(void *p) noexcept
{
	std::free(p);
}

void operator delete(void *p, std::size_t) noexcept
{
	std::free(p);
}

void operator delete(void *p, const std::nothrow_t &) noexcept
{
	std::free(p);
}

static evo_body_id add_ball(evo_world *w, double x, double y)
{
	evo_body_def d = evo_default_body_def();
	d.dynamic = 1;
	d.x = x;
	d.y = y;
	d.radius = 0.5;
	d.allow_sleep = 0;
	return evo_world_add_body(w, &d);
}

static bool is_none(evo_body_id id)
{
	return id.index == -1;
}

TEST(a_world_without_memory_is_null)
{
	fail_new = true;
	refused_news = 0;
	evo_world *w = evo_world_create(nullptr);
	fail_new = false;
	CHECK(w == nullptr);
	CHECK(refused_news > 0);
	evo_world_destroy(w);
	w = evo_world_create(nullptr);
	CHECK(w != nullptr);
	evo_world_destroy(w);
}

// A body that finds no memory for its slot is EVO_BODY_NONE; the bodies
// already there, the world's step and the next body are as if nothing
// had happened.
TEST(a_body_without_memory_is_none_and_the_world_goes_on)
{
	evo_world *w = evo_world_create(nullptr);
	CHECK(w != nullptr);
	if (!w)
		return;
	evo_body_id a = add_ball(w, 0, 0);
	CHECK(!is_none(a));
	evo_body_set_velocity(w, a, 1, 0, 0);
	fail_new = true;
	refused_news = 0;
	evo_body_id b = add_ball(w, 5, 0);
	fail_new = false;
	CHECK(refused_news > 0);
	CHECK(is_none(b));
	CHECK(!evo_body_valid(w, b));
	CHECK(evo_body_valid(w, a));
	for (int i = 0; i < 30; i++)
		evo_world_step(w);
	evo_pose p = evo_body_pose(w, a);
	CHECK(p.x > 0.5 && p.x < 1.5); /* about 1 m in 1 s */
	evo_body_id c = add_ball(w, 5, 0);
	CHECK(!is_none(c));
	CHECK(evo_body_valid(w, c));
	CHECK_EQ_INT(c.index, 1); /* the failed body took no slot */
	CHECK_EQ_INT(evo_world_remove_body(w, a), 0);
	CHECK(!evo_body_valid(w, a));
	evo_world_destroy(w);
}

// A weld that finds no memory for its id is -1 and leaves no joint: the
// two bodies still move apart, and a later weld holds.
TEST(a_weld_without_memory_is_refused_and_leaves_no_joint)
{
	evo_world *w = evo_world_create(nullptr);
	CHECK(w != nullptr);
	if (!w)
		return;
	evo_body_id a = add_ball(w, 0, 0), b = add_ball(w, 1, 0);
	fail_new = true;
	refused_news = 0;
	int j = evo_world_weld(w, a, b);
	fail_new = false;
	CHECK(refused_news > 0);
	CHECK_EQ_INT(j, -1);
	evo_body_set_velocity(w, b, 1, 0, 0);
	for (int i = 0; i < 30; i++)
		evo_world_step(w);
	CHECK(evo_body_pose(w, b).x - evo_body_pose(w, a).x > 1.5);
	j = evo_world_weld(w, a, b);
	CHECK(j >= 0);
	double gap = evo_body_pose(w, b).x - evo_body_pose(w, a).x;
	evo_body_set_velocity(w, b, 1, 0, 0);
	for (int i = 0; i < 30; i++)
		evo_world_step(w);
	double now = evo_body_pose(w, b).x - evo_body_pose(w, a).x;
	CHECK(now > gap - 0.01 && now < gap + 0.01);
	evo_world_destroy(w);
}

int main()
{
	RUN(a_world_without_memory_is_null);
	RUN(a_body_without_memory_is_none_and_the_world_goes_on);
	RUN(a_weld_without_memory_is_refused_and_leaves_no_joint);
	return test_summary();
}
