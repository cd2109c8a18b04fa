// SPDX-License-Identifier: MIT
// Error measures of a Box2D world that do not go through its broadphase: missed contacts (independent overlap
// search with b2TestOverlap), penetration (fresh contact manifolds), kinetic energy and body positions.
//
// The same source is compiled against every Box2D build (stock, quadphase, paper design); it uses only
// Box2D's public API and b2ContactManager's public members, never the broadphase under test.
#pragma once

#include <cstdint>
#include <tuple>
#include <utility>
#include <vector>

#include "box2d/box2d.h"

namespace quadphase::accuracy
{

/// One fixture child (a broadphase proxy) of a pair, ordered by (fixture address, child index).
struct ChildRef
{
    const b2Fixture* fixture;
    int32 child;

    bool operator<(const ChildRef& o) const
    {
        return std::tie(fixture, child) < std::tie(o.fixture, o.child);
    }
};
/// A pair of fixture children, the smaller first.
using ChildPair = std::pair<ChildRef, ChildRef>;

/// Result of one CheckMissedContacts call.
struct MissedContacts
{
    /// child pairs whose shapes overlap (b2TestOverlap) and that Box2D should collide
    int64_t overlapping = 0;
    int64_t missed = 0;                 ///< of those, the pairs with no b2Contact in the world's contact list
    std::vector<ChildPair> missedPairs; ///< the missed pairs (filled when asked for)
};

/// A fixture child and its tight AABB (its shape's ComputeAABB at the body's current transform).
struct ChildBox : ChildRef
{
    b2AABB box;
};

/// The tight AABB of every fixture child of `world`, in body, fixture and child order.
std::vector<ChildBox> ChildBoxes(const b2World& world);

/// The median over `boxes` of each box's larger extent, m; 0 when there are none.
float MedianExtent(const std::vector<ChildBox>& boxes);

/// Finds every pair of fixture children of `world` whose shapes overlap by b2TestOverlap at the bodies'
/// current transforms and that b2ContactManager would collide (different bodies, at least one dynamic, no
/// joint with collideConnected = false between them, the world's contact filter agrees), and counts those
/// that have no b2Contact (touching or not) for the same two fixture children. Candidates come from a uniform
/// grid over the children's tight AABBs (shape ComputeAABB), not from the world's broadphase.
///
/// Call it between steps, before anything moves a body (SetTransform, new bodies): Box2D creates the contacts
/// of such changes only in the next Step. A world whose broadphase is exact reports missed = 0 after every
/// Step. O(children + candidate pairs). Not thread-safe with respect to the world.
MissedContacts CheckMissedContacts(const b2World& world, bool keepPairs = false);

/// Penetration depths of the touching contacts at the bodies' CURRENT transforms: each enabled, non-sensor
/// touching contact's manifold is re-evaluated (b2Contact::Evaluate) and every manifold point's depth is
/// max(0, -separation) in metres. Missed contacts have no manifold and so count nothing here.
struct Penetration
{
    double maxDepth = 0.0; ///< m
    double sumDepth = 0.0; ///< m, over `points`
    int64_t points = 0;    ///< manifold points
};
Penetration MeasurePenetration(const b2World& world);

/// Kinetic energy of the dynamic bodies, J (sum of m v^2 / 2 + I w^2 / 2).
double KineticEnergy(const b2World& world);

} // namespace quadphase::accuracy
