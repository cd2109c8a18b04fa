// SPDX-License-Identifier: MIT
#include "world_check.h"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <string>

#include <catch2/catch.hpp>

#include "quadphase_scenes/scenes.h"

#if defined(QUADPHASE_VARIANT_QUADPHASE)
#include "quadphase/box2d.h"
#include "quadphase/error.h"
#endif

namespace qprobust
{
namespace
{

#if defined(QUADPHASE_VARIANT_QUADPHASE)
struct ErrorLog
{
    int count = 0;
    std::string first;
};

ErrorLog g_log;

void Record(quadphase::ErrorCode code, const char* message, void*)
{
    if (g_log.count++ == 0)
    {
        g_log.first = std::string(quadphase::ErrorCodeName(code)) + ": " + message;
    }
}
#endif

bool Finite(const b2Body& b)
{
    const b2Vec2 p = b.GetPosition();
    const b2Vec2 v = b.GetLinearVelocity();
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(b.GetAngle()) && std::isfinite(v.x) &&
           std::isfinite(v.y) && std::isfinite(b.GetAngularVelocity());
}

} // namespace

const char* VariantName()
{
#if defined(QUADPHASE_VARIANT_QUADPHASE)
    return "quadphase";
#else
    return "stock";
#endif
}

Observed StepWorld(b2World& world, int steps, const std::function<void(int)>& after)
{
    Observed seen;
    for (int step = 0; step < steps; ++step)
    {
        world.Step(1.0f / 60.0f, 8, 3);
        if (after)
        {
            after(step);
        }
        for (const b2Body* b = world.GetBodyList(); b != nullptr; b = b->GetNext())
        {
            if (b->GetType() != b2_dynamicBody)
            {
                continue;
            }
            seen.finite = seen.finite && Finite(*b);
            const float speed = b->GetLinearVelocity().Length();
            seen.maxSpeed = speed > seen.maxSpeed ? speed : seen.maxSpeed;
            seen.lowestY = std::fmin(seen.lowestY, b->GetPosition().y);
        }
        seen.steps += 1;
    }
    return seen;
}

void Print(const char* name, const Observed& seen, const char* format, ...)
{
    char extra[256];
    va_list args;
    va_start(args, format);
    std::vsnprintf(extra, sizeof(extra), format, args);
    va_end(args);
    std::printf("[%s] %s: %d steps, finite %d, max speed %.3f m/s, %s\n", VariantName(), name, seen.steps,
                int(seen.finite), double(seen.maxSpeed), extra);
}

b2Body* AddBox(b2World& world, b2BodyType type, b2Vec2 position, float hx, float hy, float density,
               float friction)
{
    b2PolygonShape shape;
    shape.SetAsBox(hx, hy);
    b2FixtureDef material;
    material.density = density;
    material.friction = friction;
    return quadphase::scenes::AddBody(world, type, position, shape, material);
}

b2Body* AddCircle(b2World& world, b2BodyType type, b2Vec2 position, float radius, float density)
{
    b2CircleShape shape;
    shape.m_radius = radius;
    b2FixtureDef material;
    material.density = density;
    material.friction = 0.6f;
    return quadphase::scenes::AddBody(world, type, position, shape, material);
}

bool AllDynamicInside(const b2World& world, const b2AABB& region)
{
    for (const b2Body* b = world.GetBodyList(); b != nullptr; b = b->GetNext())
    {
        if (b->GetType() != b2_dynamicBody)
        {
            continue;
        }
        const b2Vec2 p = b->GetPosition();
        if (!(region.lowerBound.x <= p.x && p.x <= region.upperBound.x && region.lowerBound.y <= p.y &&
              p.y <= region.upperBound.y))
        {
            return false;
        }
    }
    return true;
}

float LargestAbsX(const std::vector<b2Body*>& bodies)
{
    float largest = 0.0f;
    for (const b2Body* b : bodies)
    {
        largest = std::fmax(largest, std::fabs(b->GetPosition().x));
    }
    return largest;
}

int TouchingContacts(const b2World& world)
{
    int n = 0;
    for (const b2Contact* c = world.GetContactList(); c != nullptr; c = c->GetNext())
    {
        n += c->IsTouching() ? 1 : 0;
    }
    return n;
}

int DynamicBodies(const b2World& world)
{
    int n = 0;
    for (const b2Body* b = world.GetBodyList(); b != nullptr; b = b->GetNext())
    {
        n += b->GetType() == b2_dynamicBody ? 1 : 0;
    }
    return n;
}

Exactness::Exactness(b2World& world) : m_world(world)
{
#if defined(QUADPHASE_VARIANT_QUADPHASE)
    g_log = ErrorLog{};
    quadphase::SetErrorHandler(&Record);
    quadphase::SetValidation(m_world, true);
#endif
}

Exactness::~Exactness()
{
#if defined(QUADPHASE_VARIANT_QUADPHASE)
    quadphase::SetValidation(m_world, false);
    quadphase::SetErrorHandler(nullptr);
#endif
}

long long Exactness::Require(long long minChecks) const
{
#if defined(QUADPHASE_VARIANT_QUADPHASE)
    const quadphase::ValidationReport report = quadphase::GetValidationReport(m_world);
    INFO("validation: " << report.checks << " checks, " << report.pairsCompared << " pairs, first mismatch: "
                        << report.firstMismatch << "; first error report: " << g_log.first);
    REQUIRE(report.mismatches == 0);
    REQUIRE(g_log.count == 0);
    REQUIRE(report.checks >= minChecks);
    return report.pairsCompared;
#else
    (void)minChecks;
    return 0;
#endif
}

} // namespace qprobust
