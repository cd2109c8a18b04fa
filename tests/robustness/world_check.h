// SPDX-License-Identifier: MIT
// Helpers for the Box2D-world robustness tests, compiled once per Box2D build (stock and quadphase). Each
// test asserts the same physical criteria in both builds (no NaN, bounded speed, bodies where they must be),
// so a quadphase-only explosion or tunnelling fails the quadphase program while the stock one passes. In the
// quadphase build, Exactness also switches validation on: the shadow b2DynamicTree must agree on every pair.
#pragma once

#include <functional>
#include <vector>

#include "box2d/box2d.h"

namespace qprobust
{

/// "quadphase" or "stock": the Box2D build this program is linked with.
const char* VariantName();

/// What a run looked like, over every dynamic body after every step.
struct Observed
{
    bool finite = true;    ///< positions, angles and velocities stayed finite
    float maxSpeed = 0.0f; ///< largest linear speed of a dynamic body after any step (m/s)
    float lowestY = 1e9f;  ///< lowest centre (y) of a dynamic body after any step
    int steps = 0;
};

/// Steps `world` `steps` times at 1/60 s with 8 velocity and 3 position iterations and observes every dynamic
/// body after each step. `after(step)`, when given, runs after each step (before the observation).
Observed StepWorld(b2World& world, int steps, const std::function<void(int)>& after = {});

/// Prints one line on a run: the build, `name`, what `seen` observed, then `format` (printf's) with its arguments.
void Print(const char* name, const Observed& seen, const char* format, ...)
    __attribute__((format(printf, 3, 4)));

/// Adds a body with one box fixture (half extents hx, hy). density 0 for static bodies.
b2Body* AddBox(b2World& world, b2BodyType type, b2Vec2 position, float hx, float hy, float density,
               float friction = 0.6f);

/// Adds a body with one circle fixture.
b2Body* AddCircle(b2World& world, b2BodyType type, b2Vec2 position, float radius, float density);

/// True when every dynamic body's origin lies inside `region` (borders included).
bool AllDynamicInside(const b2World& world, const b2AABB& region);

/// The largest |x| of the bodies' positions (0 for none).
float LargestAbsX(const std::vector<b2Body*>& bodies);

/// Contacts whose fixtures touch.
int TouchingContacts(const b2World& world);

/// Number of dynamic bodies.
int DynamicBodies(const b2World& world);

/// In the quadphase build: switches validation on for `world` (the shadow b2DynamicTree compares every
/// UpdatePairs) and records every report of quadphase's error hook while it lives. In the stock build:
/// nothing.
class Exactness
{
public:
    explicit Exactness(b2World& world);
    ~Exactness();
    Exactness(const Exactness&) = delete;
    Exactness& operator=(const Exactness&) = delete;

    /// quadphase: REQUIREs zero validation mismatches, no error report, and at least `minChecks` compared
    /// UpdatePairs calls; returns the number of pairs compared. stock: returns 0.
    long long Require(long long minChecks = 1) const;

private:
    b2World& m_world;
};

} // namespace qprobust
