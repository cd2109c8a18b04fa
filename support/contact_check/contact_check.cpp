// SPDX-License-Identifier: MIT
#include "contact_check.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <unordered_map>

namespace quadphase::accuracy
{
namespace
{

ChildPair MakePair(ChildRef x, ChildRef y)
{
    return x < y ? ChildPair{x, y} : ChildPair{y, x};
}

// b2ContactManager::AddPair's rules (b2_contact_manager.cpp), without the broadphase: same body, body types
// and joints (b2Body::ShouldCollide), the world's contact filter.
bool BoxShouldCollide(const b2World& world, const ChildBox& a, const ChildBox& b)
{
    const b2Body* bodyA = a.fixture->GetBody();
    const b2Body* bodyB = b.fixture->GetBody();
    if (bodyA == bodyB)
    {
        return false;
    }
    // b2Body::ShouldCollide (private): at least one body dynamic (checked by the caller), and no joint
    // between the two bodies with collideConnected = false.
    for (const b2JointEdge* edge = bodyA->GetJointList(); edge != nullptr; edge = edge->next)
    {
        if (edge->other == bodyB && !edge->joint->GetCollideConnected())
        {
            return false;
        }
    }
    b2ContactFilter* filter = world.GetContactManager().m_contactFilter;
    return filter == nullptr ||
           filter->ShouldCollide(const_cast<b2Fixture*>(a.fixture), const_cast<b2Fixture*>(b.fixture));
}

bool ShapesOverlap(const ChildBox& a, const ChildBox& b)
{
    return b2TestOverlap(a.box, b.box) &&
           b2TestOverlap(a.fixture->GetShape(), a.child, b.fixture->GetShape(), b.child,
                         a.fixture->GetBody()->GetTransform(), b.fixture->GetBody()->GetTransform());
}

} // namespace

std::vector<ChildBox> ChildBoxes(const b2World& world)
{
    std::vector<ChildBox> boxes;
    for (const b2Body* body = world.GetBodyList(); body != nullptr; body = body->GetNext())
    {
        for (const b2Fixture* fixture = body->GetFixtureList(); fixture != nullptr;
             fixture = fixture->GetNext())
        {
            const b2Shape* shape = fixture->GetShape();
            for (int32 child = 0; child < shape->GetChildCount(); ++child)
            {
                b2AABB box;
                shape->ComputeAABB(&box, body->GetTransform(), child);
                boxes.push_back({{fixture, child}, box});
            }
        }
    }
    return boxes;
}

float MedianExtent(const std::vector<ChildBox>& boxes)
{
    std::vector<float> extents;
    extents.reserve(boxes.size());
    for (const ChildBox& p : boxes)
    {
        extents.push_back(
            std::max(p.box.upperBound.x - p.box.lowerBound.x, p.box.upperBound.y - p.box.lowerBound.y));
    }
    if (extents.empty())
    {
        return 0.0f;
    }
    std::nth_element(extents.begin(), extents.begin() + static_cast<std::ptrdiff_t>(extents.size() / 2),
                     extents.end());
    return extents[extents.size() / 2];
}

MissedContacts CheckMissedContacts(const b2World& world, bool keepPairs)
{
    MissedContacts result;
    const std::vector<ChildBox> proxies = ChildBoxes(world);

    std::set<ChildPair> contacts;
    for (const b2Contact* c = world.GetContactList(); c != nullptr; c = c->GetNext())
    {
        contacts.insert(
            MakePair({c->GetFixtureA(), c->GetChildIndexA()}, {c->GetFixtureB(), c->GetChildIndexB()}));
    }

    auto visit = [&](const ChildBox& a, const ChildBox& b) {
        if ((a.fixture->GetBody()->GetType() != b2_dynamicBody &&
             b.fixture->GetBody()->GetType() != b2_dynamicBody) ||
            !ShapesOverlap(a, b) || !BoxShouldCollide(world, a, b))
        {
            return;
        }
        ++result.overlapping;
        const ChildPair pair = MakePair(a, b);
        if (contacts.count(pair) == 0)
        {
            ++result.missed;
            if (keepPairs)
            {
                result.missedPairs.push_back(pair);
            }
        }
    };

    // Grid cell: twice the median extent of the boxes. Boxes covering more than kLargeCells cells (grounds,
    // walls) are tested against every box instead of being spread over the grid.
    const float cell = std::max(2.0f * MedianExtent(proxies), 1e-3f);
    const float inv = 1.0f / cell;
    constexpr int64_t kLargeCells = 64;

    auto cellOf = [inv](float v) {
        return static_cast<int64_t>(std::floor(v * inv));
    };
    auto cellKey = [](int64_t x, int64_t y) {
        return (static_cast<uint64_t>(x) << 32) ^ (static_cast<uint64_t>(y) & 0xffffffffull);
    };

    std::vector<int32_t> large;
    std::vector<char> isLarge(proxies.size(), 0);
    std::unordered_map<uint64_t, std::vector<int32_t>> grid;
    for (int32_t i = 0; i < static_cast<int32_t>(proxies.size()); ++i)
    {
        const b2AABB& b = proxies[i].box;
        // A non-finite box is brute-forced too (and never reaches cellOf), so nothing is silently skipped.
        const bool finite = b.lowerBound.IsValid() && b.upperBound.IsValid();
        const int64_t x0 = finite ? cellOf(b.lowerBound.x) : 0, x1 = finite ? cellOf(b.upperBound.x) : 0;
        const int64_t y0 = finite ? cellOf(b.lowerBound.y) : 0, y1 = finite ? cellOf(b.upperBound.y) : 0;
        if (!finite || (x1 - x0 + 1) * (y1 - y0 + 1) > kLargeCells)
        {
            large.push_back(i);
            isLarge[static_cast<size_t>(i)] = 1;
            continue;
        }
        for (int64_t x = x0; x <= x1; ++x)
        {
            for (int64_t y = y0; y <= y1; ++y)
            {
                grid[cellKey(x, y)].push_back(i);
            }
        }
    }

    // Grid pairs: each pair is visited once, in the cell that holds the corner (max of the lower bounds).
    for (const auto& entry : grid)
    {
        const std::vector<int32_t>& members = entry.second;
        for (size_t i = 0; i < members.size(); ++i)
        {
            const ChildBox& a = proxies[members[i]];
            for (size_t j = i + 1; j < members.size(); ++j)
            {
                const ChildBox& b = proxies[members[j]];
                const int64_t cx = cellOf(std::max(a.box.lowerBound.x, b.box.lowerBound.x));
                const int64_t cy = cellOf(std::max(a.box.lowerBound.y, b.box.lowerBound.y));
                if (cellKey(cx, cy) == entry.first)
                {
                    visit(a, b);
                }
            }
        }
    }
    // Large boxes against everything (each pair once: a large box against a smaller index among the large
    // ones).
    for (const int32_t i : large)
    {
        for (int32_t j = 0; j < static_cast<int32_t>(proxies.size()); ++j)
        {
            // Not i itself, nor a large box of smaller index (visited when j was the large one).
            if (j != i && (isLarge[static_cast<size_t>(j)] == 0 || j > i))
            {
                visit(proxies[i], proxies[j]);
            }
        }
    }
    return result;
}

Penetration MeasurePenetration(const b2World& world)
{
    Penetration result;
    for (const b2Contact* c = world.GetContactList(); c != nullptr; c = c->GetNext())
    {
        if (!c->IsTouching() || !c->IsEnabled() || c->GetFixtureA()->IsSensor() ||
            c->GetFixtureB()->IsSensor())
        {
            continue;
        }
        const b2Body* bodyA = c->GetFixtureA()->GetBody();
        const b2Body* bodyB = c->GetFixtureB()->GetBody();
        b2Manifold manifold;
        // Evaluate is not const in Box2D's API but only writes `manifold`.
        const_cast<b2Contact*>(c)->Evaluate(&manifold, bodyA->GetTransform(), bodyB->GetTransform());
        if (manifold.pointCount == 0)
        {
            continue;
        }
        b2WorldManifold wm;
        wm.Initialize(&manifold, bodyA->GetTransform(), c->GetFixtureA()->GetShape()->m_radius,
                      bodyB->GetTransform(), c->GetFixtureB()->GetShape()->m_radius);
        for (int32 i = 0; i < manifold.pointCount; ++i)
        {
            const double depth = std::max(0.0, -static_cast<double>(wm.separations[i]));
            result.maxDepth = std::max(result.maxDepth, depth);
            result.sumDepth += depth;
            ++result.points;
        }
    }
    return result;
}

double KineticEnergy(const b2World& world)
{
    double energy = 0.0;
    for (const b2Body* body = world.GetBodyList(); body != nullptr; body = body->GetNext())
    {
        if (body->GetType() != b2_dynamicBody)
        {
            continue;
        }
        const b2Vec2 v = body->GetLinearVelocity();
        const double w = body->GetAngularVelocity();
        // GetInertia() is about the body origin; the rotational energy needs the inertia about the centre of
        // mass.
        const b2Vec2 c = body->GetLocalCenter();
        const double inertia =
            double(body->GetInertia()) - double(body->GetMass()) * (double(c.x) * c.x + double(c.y) * c.y);
        energy += 0.5 * body->GetMass() * (double(v.x) * v.x + double(v.y) * v.y) + 0.5 * inertia * w * w;
    }
    return energy;
}

} // namespace quadphase::accuracy
