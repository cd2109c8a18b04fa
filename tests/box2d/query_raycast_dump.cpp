// SPDX-License-Identifier: MIT
// Dumps the answers of b2World::QueryAABB and b2World::RayCast on a set of worlds, in a text form that does
// not depend on the broadphase's traversal order. The same source is compiled against both Box2D builds
// (qp_query_dump_quadphase, qp_query_dump_stock); tests/box2d/CompareDumps.cmake runs both and requires
// byte-identical output.
//
// Why the worlds are identical in both builds: stepping a world with contacts diverges between the builds
// (the pairs come in another order, so do the contacts and the solver), so the worlds are brought into a
// varied state without contacts instead:
//   1. build a scene (quadphase::scenes); call its perStep spawner 200 times without stepping;
//   2. teleport every dynamic body (SetTransform -> MoveProxy) to a pseudo-random position and angle in the
//      scene's region (the bounding box of the initial fixtures), about 1% of them far outside it;
//   3. give them random velocities, switch every fixture's collision filter off (maskBits 0: no contact at
//      all, so every body is its own island and the solver follows the body list), and step 3 times: the
//      bodies fly ballistically and MoveProxy gets real displacements (fat boxes stretched along the motion);
//   4. restore the filters, nudge every 3rd dynamic body by a few cm (MoveProxy keeps or replaces the stored
//      box), disable every 17th body (DestroyProxy; every other one is enabled again: CreateProxy), destroy
//      every 23rd, then Step(0): new contacts and narrow phase, nothing moves.
// The fat boxes follow Box2D's policy bit for bit in both builds, so the answers must be the same.
//
// Then ~300 QueryAABB boxes (tiny, cell-sized, aligned to the cells of a power-of-two grid, huge, outside the
// world, zero-area, touching a fat box exactly or missing it by one ulp) and ~300 rays (short, long, 45
// degrees, axis-aligned, along exact cell borders and fat-box edges, starting outside the world, 9 region
// sides long) are asked. Per box: the sorted multiset of reported fixtures, and the number of calls when the
// callback stops at the first (0 or 1). Per ray: all hits (callback returns 1), the closest hit (returns the
// fraction), the closest hit of odd bodies (returns -1 for even ones), any hit (returns 0). Fixtures are
// named "body.fixture": body index in creation order, fixture index in the body's list.
//
// Self-checks in both builds (failures exit 1): stop-at-first calls == (anything reported ? 1 : 0), for
// boxes and rays; closest and filtered-closest fractions == the minimum of the all-hits ones, and no report
// beyond the fraction the ray was clipped to; all hits == a brute-force ray cast of every fixture child (see
// DumpRays); every fixture child whose tight box overlaps a box is reported, at most once per child; enough
// boxes and rays found something (and not all of them).
//
// Usage: qp_query_dump_<variant> <output file> [--validate] [--grid]
//   --validate  quadphase build only: quadphase::SetValidation on every world; exits 1 on any mismatch.
//   --grid      quadphase build only: quadphase::Configure the quadtree to the power-of-two grid the queries
//               are aligned to (fixed bounds and depth), so "cell borders" are the quadtree's own.
// Diagnostics go to stderr; the output file holds only the answers.
#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "../core/slab_clip.h"
#include "box2d/box2d.h"
#include "quadphase_scenes/scenes.h"

#if QUADPHASE_VARIANT_QUADPHASE
#include "quadphase/box2d.h"
#endif

namespace
{

using quadphase::scenes::Rng;
using quadphase::scenes::SceneId;

struct Case
{
    SceneId id;
    int size;
    uint32_t seed;
};

// Every scene at least once (checked at start-up), sizes chosen to keep the whole run to a few seconds.
const Case kCases[] = {
    {SceneId::Rain, 3000, 1},       {SceneId::Tiles, 4000, 2},  {SceneId::Pyramid, 20, 3},
    {SceneId::Particles, 3000, 4},  {SceneId::Sparse, 2000, 5}, {SceneId::Bullets, 200, 6},
    {SceneId::Tumbler, 400, 7},     {SceneId::Rain, 500, 8},    {SceneId::Shooter, 200, 9},
    {SceneId::OpenWorld, 1000, 10}, {SceneId::Mixed, 1000, 11}, {SceneId::Terrain, 300, 12},
    {SceneId::Churn, 500, 13},
};

constexpr int kSpawnSteps = 200; // perStep calls (tumbler and bullets create their bodies there)
constexpr int kBallisticSteps = 3;
constexpr int kQueriesPerScene = 300;
constexpr int kRaysPerScene = 300;

int g_failures = 0;

void Fail(const char* format, ...)
{
    ++g_failures;
    if (g_failures > 50)
    {
        return;
    }
    std::va_list args;
    va_start(args, format);
    std::fputs("qp_query_dump: FAILED: ", stderr);
    std::vfprintf(stderr, format, args);
    std::fputc('\n', stderr);
    va_end(args);
}

// --------------------------------------------------------------------------------------------------------
// Output

class Out
{
public:
    void Printf(const char* format, ...)
    {
        char buffer[512];
        std::va_list args;
        va_start(args, format);
        const int n = std::vsnprintf(buffer, sizeof(buffer), format, args);
        va_end(args);
        if (n > 0)
        {
            m_text.append(buffer, std::min(size_t(n), sizeof(buffer) - 1));
        }
    }
    std::string& Text() { return m_text; }

private:
    std::string m_text;
};

// %.9g round-trips every float exactly; -0 and 0 print differently, which is wanted.
std::string F(float v)
{
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.9g", double(v));
    return buffer;
}

std::string V(const b2Vec2& v)
{
    return "(" + F(v.x) + " " + F(v.y) + ")";
}

std::string Box(const b2AABB& b)
{
    return "[" + F(b.lowerBound.x) + " " + F(b.lowerBound.y) + " " + F(b.upperBound.x) + " " +
           F(b.upperBound.y) + "]";
}

// --------------------------------------------------------------------------------------------------------
// Fixture names

struct FixtureId
{
    int32_t body;
    int32_t fixture;
    bool operator<(const FixtureId& o) const { return std::tie(body, fixture) < std::tie(o.body, o.fixture); }
    bool operator==(const FixtureId& o) const { return body == o.body && fixture == o.fixture; }
};

std::string Name(const FixtureId& id)
{
    return std::to_string(id.body) + "." + std::to_string(id.fixture);
}

struct FixtureInfo
{
    b2Fixture* fixture;
    FixtureId id;
};

class Names
{
public:
    explicit Names(b2World& world)
    {
        std::vector<b2Body*> bodies;
        for (b2Body* b = world.GetBodyList(); b != nullptr; b = b->GetNext())
        {
            bodies.push_back(b);
        }
        std::reverse(bodies.begin(), bodies.end()); // the list is in reverse creation order
        for (size_t i = 0; i < bodies.size(); ++i)
        {
            int32_t k = 0;
            for (b2Fixture* f = bodies[i]->GetFixtureList(); f != nullptr; f = f->GetNext(), ++k)
            {
                const FixtureId id{int32_t(i), k};
                m_ids.emplace(f, id);
                m_fixtures.push_back({f, id});
            }
        }
    }
    FixtureId Of(b2Fixture* f) const
    {
        const auto it = m_ids.find(f);
        if (it == m_ids.end())
        {
            Fail("callback reported a fixture that is not in the world");
            return {-1, -1};
        }
        return it->second;
    }
    const std::vector<FixtureInfo>& All() const { return m_fixtures; }

private:
    std::unordered_map<const b2Fixture*, FixtureId> m_ids;
    std::vector<FixtureInfo> m_fixtures; // creation order of bodies
};

// --------------------------------------------------------------------------------------------------------
// Callbacks

class CollectQuery : public b2QueryCallback
{
public:
    explicit CollectQuery(const Names& names) : m_names(names) {}
    bool ReportFixture(b2Fixture* fixture) override
    {
        found.push_back(m_names.Of(fixture));
        return true;
    }
    std::vector<FixtureId> found;

private:
    const Names& m_names;
};

class FirstQuery : public b2QueryCallback
{
public:
    bool ReportFixture(b2Fixture*) override
    {
        ++calls;
        return false;
    }
    int calls = 0;
};

struct Hit
{
    FixtureId id;
    float fraction;
    b2Vec2 point;
    b2Vec2 normal;
    bool operator<(const Hit& o) const
    {
        return std::make_tuple(id.body, id.fixture, fraction, point.x, point.y, normal.x, normal.y) <
               std::make_tuple(o.id.body, o.id.fixture, o.fraction, o.point.x, o.point.y, o.normal.x,
                               o.normal.y);
    }
    bool operator==(const Hit& o) const
    {
        // Bitwise, so that -0 and 0 differ and NaN equals itself.
        return id == o.id && std::memcmp(&fraction, &o.fraction, sizeof(float)) == 0 &&
               std::memcmp(&point, &o.point, sizeof(b2Vec2)) == 0 &&
               std::memcmp(&normal, &o.normal, sizeof(b2Vec2)) == 0;
    }
};

class AllHits : public b2RayCastCallback
{
public:
    explicit AllHits(const Names& names) : m_names(names) {}
    float ReportFixture(b2Fixture* fixture, const b2Vec2& point, const b2Vec2& normal,
                        float fraction) override
    {
        hits.push_back({m_names.Of(fixture), fraction, point, normal});
        return 1.0f;
    }
    std::vector<Hit> hits;

private:
    const Names& m_names;
};

// Closest hit: returns the fraction (the usual Box2D pattern). With skipEven, fixtures of even bodies are
// filtered out (returns -1), which must not clip the ray.
class ClosestHit : public b2RayCastCallback
{
public:
    ClosestHit(const Names& names, bool skipEven) : m_names(names), m_skipEven(skipEven) {}
    float ReportFixture(b2Fixture* fixture, const b2Vec2& point, const b2Vec2&, float fraction) override
    {
        if (m_skipEven && m_names.Of(fixture).body % 2 == 0)
        {
            return -1.0f;
        }
        // Box2D clips the ray to the returned fraction, so no later report may lie beyond it: the usual
        // "remember the last report" callback relies on that.
        if (hit && fraction > clip)
        {
            ++beyondClip;
        }
        if (!hit || fraction < best)
        {
            best = fraction;
            bestPoint = point;
        }
        hit = true;
        clip = fraction;
        last = fraction;
        return fraction;
    }
    bool hit = false;
    float best = 0.0f;
    b2Vec2 bestPoint{0.0f, 0.0f};
    float clip = 1.0f;
    float last = 0.0f; // fraction of the last report: what a "remember the last report" callback would keep
    int beyondClip = 0;

private:
    const Names& m_names;
    bool m_skipEven;
};

class AnyHit : public b2RayCastCallback
{
public:
    float ReportFixture(b2Fixture*, const b2Vec2&, const b2Vec2&, float) override
    {
        ++calls;
        return 0.0f;
    }
    int calls = 0;
};

// --------------------------------------------------------------------------------------------------------
// The grid the queries are aligned to: a power-of-two square with a power-of-two leaf, so every cell border
// at every level is an exact float.

struct Grid
{
    float x0 = 0.0f;
    float y0 = 0.0f;
    float side = 1.0f;
    int depth = 0;

    float CellSide(int level) const { return std::ldexp(side, -level); }
    float X(int level, int i) const { return x0 + float(i) * CellSide(level); }
    float Y(int level, int j) const { return y0 + float(j) * CellSide(level); }
    float Leaf() const { return CellSide(depth); }
    /// A uniform random point of the grid's square grown by `margin` on every side.
    b2Vec2 RandomPoint(Rng& rng, float margin) const
    {
        return b2Vec2(x0 - margin + (side + 2.0f * margin) * rng.Uniform01(),
                      y0 - margin + (side + 2.0f * margin) * rng.Uniform01());
    }
};

float PowerOfTwoAtLeast(float v)
{
    float p = 1.0f / 1024.0f;
    while (p < v)
    {
        p *= 2.0f;
    }
    return p;
}

// Region of the initial fixtures, median fixture extent -> grid (depth like the automatic rule: leaf about
// 2 x the median fat extent, at most 2 leaf cells per fixture).
Grid MakeGrid(const b2AABB& region, float medianFatExtent, int32_t fixtureCount)
{
    Grid g;
    const float extent =
        std::max(region.upperBound.x - region.lowerBound.x, region.upperBound.y - region.lowerBound.y);
    g.side = PowerOfTwoAtLeast(extent * 1.0625f);
    g.depth = 0;
    while (g.depth < 12 && g.CellSide(g.depth) > 2.0f * medianFatExtent &&
           std::ldexp(1.0, 2 * (g.depth + 1)) <= 2.0 * double(fixtureCount))
    {
        ++g.depth;
    }
    // Origin: a multiple of the leaf side, so borders are exact.
    const float leaf = g.Leaf();
    const float cx = 0.5f * (region.lowerBound.x + region.upperBound.x);
    const float cy = 0.5f * (region.lowerBound.y + region.upperBound.y);
    g.x0 = std::floor((cx - 0.5f * g.side) / leaf) * leaf;
    g.y0 = std::floor((cy - 0.5f * g.side) / leaf) * leaf;
    return g;
}

// --------------------------------------------------------------------------------------------------------
// Bringing the world into its state (see the file comment).

b2AABB FixtureRegion(b2World& world)
{
    b2AABB r;
    r.lowerBound.Set(FLT_MAX, FLT_MAX);
    r.upperBound.Set(-FLT_MAX, -FLT_MAX);
    for (b2Body* b = world.GetBodyList(); b != nullptr; b = b->GetNext())
    {
        for (b2Fixture* f = b->GetFixtureList(); f != nullptr; f = f->GetNext())
        {
            for (int32 c = 0; c < f->GetShape()->GetChildCount(); ++c)
            {
                r.Combine(f->GetAABB(c));
            }
        }
    }
    return r;
}

float MedianFatExtent(b2World& world)
{
    std::vector<float> e;
    for (b2Body* b = world.GetBodyList(); b != nullptr; b = b->GetNext())
    {
        for (b2Fixture* f = b->GetFixtureList(); f != nullptr; f = f->GetNext())
        {
            for (int32 c = 0; c < f->GetShape()->GetChildCount(); ++c)
            {
                const b2AABB& a = f->GetAABB(c);
                e.push_back(std::max(a.upperBound.x - a.lowerBound.x, a.upperBound.y - a.lowerBound.y) +
                            2.0f * b2_aabbExtension);
            }
        }
    }
    if (e.empty())
    {
        return 1.0f;
    }
    std::nth_element(e.begin(), e.begin() + std::ptrdiff_t(e.size() / 2), e.end());
    return e[e.size() / 2];
}

std::vector<b2Body*> BodiesInCreationOrder(b2World& world)
{
    std::vector<b2Body*> bodies;
    for (b2Body* b = world.GetBodyList(); b != nullptr; b = b->GetNext())
    {
        bodies.push_back(b);
    }
    std::reverse(bodies.begin(), bodies.end());
    return bodies;
}

// A chain loop and an edge around the region (multi-child proxies and thin boxes), plus a body with several
// fixtures, so that chains, edges and fixture indices > 0 are covered in every scene.
void AddExtraBodies(b2World& world, const b2AABB& region, Rng& rng)
{
    const float w = region.upperBound.x - region.lowerBound.x;
    const float h = region.upperBound.y - region.lowerBound.y;
    b2BodyDef bd;
    b2Body* frame = world.CreateBody(&bd);
    {
        std::vector<b2Vec2> loop;
        const int n = 24;
        for (int i = 0; i < n; ++i)
        {
            const float a = 2.0f * b2_pi * float(i) / float(n);
            const float r = 0.45f + 0.1f * rng.Uniform01();
            loop.emplace_back(region.lowerBound.x + w * (0.5f + r * std::cos(a)),
                              region.lowerBound.y + h * (0.5f + r * std::sin(a)));
        }
        b2ChainShape chain;
        chain.CreateLoop(loop.data(), int32(loop.size()));
        frame->CreateFixture(&chain, 0.0f);
    }
    {
        b2EdgeShape edge;
        edge.SetTwoSided(b2Vec2(region.lowerBound.x, region.lowerBound.y + 0.25f * h),
                         b2Vec2(region.upperBound.x, region.lowerBound.y + 0.75f * h));
        frame->CreateFixture(&edge, 0.0f);
    }

    bd.type = b2_dynamicBody;
    bd.position.Set(region.lowerBound.x + 0.5f * w, region.lowerBound.y + 0.5f * h);
    b2Body* cluster = world.CreateBody(&bd);
    for (int i = 0; i < 4; ++i)
    {
        b2PolygonShape box;
        box.SetAsBox(0.3f + 0.2f * float(i), 0.2f, b2Vec2(float(i) - 1.5f, 0.5f * float(i)), 0.3f * float(i));
        cluster->CreateFixture(&box, 1.0f);
        b2CircleShape circle;
        circle.m_radius = 0.25f;
        circle.m_p.Set(float(i) - 1.5f, -1.0f);
        cluster->CreateFixture(&circle, 1.0f);
    }
}

struct Prepared
{
    Grid grid;
    b2AABB region;
    std::vector<b2Vec2> farPoints; // where far-away bodies were sent
    int disabled = 0;
    int destroyed = 0;
};

Prepared Prepare(quadphase::scenes::Scene& scene, uint32_t seed, bool validate, bool configureGrid)
{
    b2World& world = *scene.world;
    Prepared p;
    Rng rng(seed * 2654435761u + 12345u);

#if QUADPHASE_VARIANT_QUADPHASE
    if (validate)
    {
        quadphase::SetValidation(world, true);
    }
#else
    (void)validate;
    (void)configureGrid;
#endif

    if (scene.perStep)
    {
        for (int s = 0; s < kSpawnSteps; ++s)
        {
            scene.perStep(world, s); // spawns bodies; no stepping
        }
    }

    p.region = FixtureRegion(world);
    AddExtraBodies(world, p.region, rng);
    p.grid = MakeGrid(p.region, MedianFatExtent(world), world.GetProxyCount());

#if QUADPHASE_VARIANT_QUADPHASE
    if (configureGrid)
    {
        quadphase::Config config = quadphase::GetConfig(world);
        config.depth = p.grid.depth;
        config.autoBounds = false;
        config.bounds = {p.grid.x0, p.grid.y0, p.grid.x0 + p.grid.side, p.grid.y0 + p.grid.side};
        quadphase::Configure(world, config);
    }
#endif

    const b2AABB& r = p.region;
    const float w = r.upperBound.x - r.lowerBound.x;
    const float h = r.upperBound.y - r.lowerBound.y;
    const b2Vec2 centre = r.GetCenter();
    const float size = std::max(w, h);

    // 2. Teleport every dynamic body, in creation order.
    std::vector<b2Body*> bodies = BodiesInCreationOrder(world);
    int dynamicIndex = 0;
    for (b2Body* b : bodies)
    {
        if (b->GetType() != b2_dynamicBody)
        {
            continue;
        }
        b2Vec2 pos(r.lowerBound.x + w * rng.Uniform01(), r.lowerBound.y + h * rng.Uniform01());
        const float angle = rng.Uniform(-b2_pi, b2_pi);
        if (dynamicIndex % 97 == 5)
        {
            const float a = rng.Uniform(-b2_pi, b2_pi);
            const float d = size * rng.Uniform(3.0f, 30.0f);
            pos = centre + b2Vec2(d * std::cos(a), d * std::sin(a));
            p.farPoints.push_back(pos);
        }
        b->SetTransform(pos, angle);
        ++dynamicIndex;
    }

    // 3. Ballistic steps without contacts.
    std::vector<std::pair<b2Fixture*, b2Filter>> filters;
    for (b2Body* b : bodies)
    {
        for (b2Fixture* f = b->GetFixtureList(); f != nullptr; f = f->GetNext())
        {
            filters.emplace_back(f, f->GetFilterData());
            b2Filter none = f->GetFilterData();
            none.maskBits = 0;
            none.groupIndex = 0;
            f->SetFilterData(none);
        }
        if (b->GetType() == b2_dynamicBody)
        {
            // Up to 1.25 m per step, a fifth of them at rest (gravity still moves them a little).
            const bool rest = rng.Index(5) == 0;
            const float speed = rest ? 0.0f : rng.Uniform(0.0f, 75.0f);
            const float a = rng.Uniform(-b2_pi, b2_pi);
            b->SetLinearVelocity(b2Vec2(speed * std::cos(a), speed * std::sin(a)));
            b->SetAngularVelocity(rest ? 0.0f : rng.Uniform(-10.0f, 10.0f));
            b->SetAwake(true);
        }
    }
    for (int s = 0; s < kBallisticSteps; ++s)
    {
        world.Step(scene.timeStep, scene.velocityIterations, scene.positionIterations);
    }
    if (world.GetContactCount() != 0)
    {
        Fail("ballistic steps made %d contacts (they must make none, or the builds diverge)",
             int(world.GetContactCount()));
    }
    for (auto& [f, filter] : filters)
    {
        f->SetFilterData(filter);
    }

    // 4. Nudge, disable, re-enable, destroy.
    int k = 0;
    for (b2Body* b : bodies)
    {
        const int i = k++;
        if (b->GetType() != b2_dynamicBody)
        {
            continue;
        }
        if (i % 3 == 1)
        {
            const b2Vec2 d(rng.Uniform(-0.05f, 0.05f), rng.Uniform(-0.05f, 0.05f));
            b->SetTransform(b->GetPosition() + d, b->GetAngle() + rng.Uniform(-0.01f, 0.01f));
        }
    }
    k = 0;
    std::vector<b2Body*> toDestroy;
    for (b2Body* b : bodies)
    {
        const int i = k++;
        if (i % 17 == 3)
        {
            b->SetEnabled(false);
            ++p.disabled;
        }
        if (i % 34 == 3)
        {
            b->SetEnabled(true);
            --p.disabled;
        }
        if (i % 23 == 7 && i > 0)
        {
            toDestroy.push_back(b);
        }
    }
    for (b2Body* b : toDestroy)
    {
        world.DestroyBody(b);
        ++p.destroyed;
    }
    world.Step(0.0f, scene.velocityIterations, scene.positionIterations); // pairs and narrow phase only
    return p;
}

// --------------------------------------------------------------------------------------------------------
// Queries

b2AABB MakeBox(float x0, float y0, float x1, float y1)
{
    b2AABB b;
    b.lowerBound.Set(std::min(x0, x1), std::min(y0, y1));
    b.upperBound.Set(std::max(x0, x1), std::max(y0, y1));
    return b;
}

b2AABB Around(const b2Vec2& c, float hx, float hy)
{
    return MakeBox(c.x - hx, c.y - hy, c.x + hx, c.y + hy);
}

// Box2D's fat box of a proxy created or replaced from `tight` (b2DynamicTree::CreateProxy/MoveProxy).
b2AABB Fatten(const b2AABB& tight)
{
    const b2Vec2 r(b2_aabbExtension, b2_aabbExtension);
    b2AABB fat;
    fat.lowerBound = tight.lowerBound - r;
    fat.upperBound = tight.upperBound + r;
    return fat;
}

struct Live
{
    b2Fixture* fixture;
    FixtureId id;
    int32 child;
};

std::vector<Live> LiveChildren(const Names& names)
{
    std::vector<Live> live;
    for (const FixtureInfo& info : names.All())
    {
        if (!info.fixture->GetBody()->IsEnabled())
        {
            continue;
        }
        for (int32 c = 0; c < info.fixture->GetShape()->GetChildCount(); ++c)
        {
            live.push_back({info.fixture, info.id, c});
        }
    }
    return live;
}

// Random points of the grid and random live fixture children, for MakeQueries and MakeRays.
struct Draws
{
    const Grid& g;
    const std::vector<Live>& live;
    Rng& rng;

    b2Vec2 InGrid(float margin) const { return g.RandomPoint(rng, margin); }
    const Live& RandomLive() const { return live[rng.Index(uint32_t(live.size()))]; }
};

std::vector<b2AABB> MakeQueries(const Prepared& p, const std::vector<Live>& live, Rng& rng)
{
    const Grid& g = p.grid;
    const float leaf = g.Leaf();
    const float side = g.side;
    const Draws d{g, live, rng};

    std::vector<b2AABB> q;
    // Tiny.
    for (int i = 0; i < 40; ++i)
    {
        const b2Vec2 c = (i % 2 == 0) ? d.InGrid(0.0f) : d.RandomLive().fixture->GetAABB(0).GetCenter();
        q.push_back(Around(c, rng.Uniform(0.001f, 0.05f), rng.Uniform(0.001f, 0.05f)));
    }
    // About one leaf cell, anywhere.
    for (int i = 0; i < 40; ++i)
    {
        q.push_back(Around(d.InGrid(leaf), leaf * rng.Uniform(0.3f, 0.7f), leaf * rng.Uniform(0.3f, 0.7f)));
    }
    // Exactly one or more cells of some level; a third of them collapsed onto a cell border line or corner.
    for (int i = 0; i < 40; ++i)
    {
        const int level = int(rng.Index(uint32_t(g.depth + 1)));
        const int n = 1 << level;
        const int ix = int(rng.Index(uint32_t(n)));
        const int iy = int(rng.Index(uint32_t(n)));
        const int sx = 1 + int(rng.Index(2));
        const int sy = 1 + int(rng.Index(2));
        float x0 = g.X(level, ix), y0 = g.Y(level, iy), x1 = g.X(level, ix + sx), y1 = g.Y(level, iy + sy);
        switch (i % 6)
        {
        case 1:
            x1 = x0;
            break;
        case 3:
            y1 = y0;
            break;
        case 5:
            x1 = x0;
            y1 = y0;
            break;
        default:
            break;
        }
        q.push_back(MakeBox(x0, y0, x1, y1));
    }
    // Medium to large.
    for (int i = 0; i < 30; ++i)
    {
        q.push_back(Around(d.InGrid(0.0f), side * rng.Uniform(1.0f / 32.0f, 0.5f),
                           side * rng.Uniform(1.0f / 32.0f, 0.5f)));
    }
    // Huge.
    q.push_back(MakeBox(g.x0, g.y0, g.x0 + side, g.y0 + side));
    q.push_back(p.region);
    q.push_back(MakeBox(g.x0 - side, g.y0 - side, g.x0 + 2.0f * side, g.y0 + 2.0f * side));
    q.push_back(MakeBox(-1.0e9f, -1.0e9f, 1.0e9f, 1.0e9f));
    q.push_back(MakeBox(-FLT_MAX, -FLT_MAX, FLT_MAX, FLT_MAX));
    q.push_back(MakeBox(g.x0, -1.0e9f, g.x0 + 0.5f * side, 1.0e9f)); // a tall strip
    // Outside the grid: beside each side, far away, and around the bodies sent far away.
    for (int i = 0; i < 30; ++i)
    {
        const float gap = side * rng.Uniform(0.01f, 2.0f);
        const float s = side * rng.Uniform(0.001f, 0.3f);
        const float t = g.x0 + side * rng.Uniform(-0.5f, 1.5f);
        const float u = g.y0 + side * rng.Uniform(-0.5f, 1.5f);
        switch (i % 5)
        {
        case 0:
            q.push_back(MakeBox(g.x0 - gap - s, u, g.x0 - gap, u + s));
            break;
        case 1:
            q.push_back(MakeBox(g.x0 + side + gap, u, g.x0 + side + gap + s, u + s));
            break;
        case 2:
            q.push_back(MakeBox(t, g.y0 - gap - s, t + s, g.y0 - gap));
            break;
        case 3:
            q.push_back(MakeBox(t, g.y0 + side + gap, t + s, g.y0 + side + gap + s));
            break;
        default:
            if (!p.farPoints.empty())
            {
                const b2Vec2 c = p.farPoints[rng.Index(uint32_t(p.farPoints.size()))];
                q.push_back(Around(c, rng.Uniform(0.5f, 20.0f), rng.Uniform(0.5f, 20.0f)));
            }
            else
            {
                q.push_back(Around(b2Vec2(g.x0 + 50.0f * side, g.y0 - 40.0f * side), s, s));
            }
            break;
        }
    }
    // Zero width, zero height, zero area.
    for (int i = 0; i < 30; ++i)
    {
        const b2Vec2 c = (i % 3 == 0) ? d.RandomLive().fixture->GetAABB(0).GetCenter() : d.InGrid(0.0f);
        const float l = side * rng.Uniform(0.0f, 0.2f);
        switch (i % 3)
        {
        case 0:
            q.push_back(MakeBox(c.x, c.y, c.x, c.y));
            break;
        case 1:
            q.push_back(MakeBox(c.x, c.y, c.x + l, c.y));
            break;
        default:
            q.push_back(MakeBox(c.x, c.y, c.x, c.y + l));
            break;
        }
    }
    // On the edges of fat boxes: touching (borders overlap in Box2D), one ulp away, zero-area at a corner,
    // the fat box itself, the tight box.
    for (int i = 0; i < 60; ++i)
    {
        const Live& l = d.RandomLive();
        const b2AABB fat = Fatten(l.fixture->GetAABB(l.child));
        const float s = rng.Uniform(0.01f, 2.0f);
        const float up = std::nextafter(fat.upperBound.x, FLT_MAX);
        const float downY = std::nextafter(fat.lowerBound.y, -FLT_MAX);
        switch (i % 8)
        {
        case 0:
            q.push_back(
                MakeBox(fat.upperBound.x, fat.upperBound.y, fat.upperBound.x + s, fat.upperBound.y + s));
            break;
        case 1:
            q.push_back(MakeBox(up, fat.lowerBound.y, up + s, fat.upperBound.y));
            break;
        case 2:
            q.push_back(MakeBox(fat.lowerBound.x, fat.lowerBound.y, fat.lowerBound.x, fat.lowerBound.y));
            break;
        case 3:
            q.push_back(fat);
            break;
        case 4:
            q.push_back(MakeBox(fat.lowerBound.x - s, fat.lowerBound.y, fat.lowerBound.x, fat.upperBound.y));
            break;
        case 5:
            q.push_back(MakeBox(fat.lowerBound.x, downY - s, fat.upperBound.x, downY));
            break;
        case 6:
            q.push_back(MakeBox(fat.lowerBound.x, fat.upperBound.y, fat.upperBound.x, fat.upperBound.y));
            break;
        default:
            q.push_back(l.fixture->GetAABB(l.child));
            break;
        }
    }
    // Fill up with random boxes of any size.
    while (int(q.size()) < kQueriesPerScene)
    {
        const float s = std::ldexp(side, -int(rng.Index(uint32_t(g.depth + 4))));
        q.push_back(Around(d.InGrid(0.1f * side), s * rng.Uniform01(), s * rng.Uniform01()));
    }
    return q;
}

// --------------------------------------------------------------------------------------------------------
// Rays

struct Ray
{
    b2Vec2 p1;
    b2Vec2 p2;
};

std::vector<Ray> MakeRays(const Prepared& p, const std::vector<Live>& live, Rng& rng)
{
    const Grid& g = p.grid;
    const float leaf = g.Leaf();
    const float side = g.side;
    const Draws d{g, live, rng};
    auto direction = [&]() {
        const float a = rng.Uniform(-b2_pi, b2_pi);
        return b2Vec2(std::cos(a), std::sin(a));
    };

    std::vector<Ray> rays;
    auto add = [&](const b2Vec2& a, const b2Vec2& b) {
        if (a.x != b.x || a.y != b.y) // Box2D requires a non-zero ray
        {
            rays.push_back({a, b});
        }
    };
    // Short, from anywhere or from a fixture's neighbourhood.
    for (int i = 0; i < 40; ++i)
    {
        const b2Vec2 a = (i % 2 == 0)
                             ? d.InGrid(0.0f)
                             : d.RandomLive().fixture->GetAABB(0).GetCenter() + 0.5f * leaf * direction();
        add(a, a + leaf * rng.Uniform(0.1f, 3.0f) * direction());
    }
    // Long, across the world.
    for (int i = 0; i < 40; ++i)
    {
        add(d.InGrid(0.0f), d.InGrid(0.0f));
    }
    // 45 degrees.
    for (int i = 0; i < 30; ++i)
    {
        const b2Vec2 a = d.InGrid(0.0f);
        const float d = side * rng.Uniform(0.01f, 0.7f);
        add(a, a + b2Vec2((i & 1) ? d : -d, (i & 2) ? d : -d));
    }
    // Axis-aligned, short and long, both directions.
    for (int i = 0; i < 40; ++i)
    {
        const b2Vec2 a = d.InGrid(0.0f);
        const float d = (i % 4 < 2 ? leaf * rng.Uniform(0.5f, 4.0f) : side * rng.Uniform(0.2f, 1.0f)) *
                        ((i & 1) ? 1.0f : -1.0f);
        add(a, (i % 8 < 4) ? a + b2Vec2(d, 0.0f) : a + b2Vec2(0.0f, d));
    }
    // Along exact cell borders of some level, and diagonals through cell corners.
    for (int i = 0; i < 40; ++i)
    {
        const int level = int(rng.Index(uint32_t(g.depth + 1)));
        const int n = 1 << level;
        const int k = int(rng.Index(uint32_t(n + 1)));
        const int a = int(rng.Index(uint32_t(n)));
        const int b = int(rng.Index(uint32_t(n + 1)));
        switch (i % 4)
        {
        case 0:
            add(b2Vec2(g.X(level, k), g.Y(level, a)), b2Vec2(g.X(level, k), g.Y(level, b)));
            break;
        case 1:
            add(b2Vec2(g.X(level, a), g.Y(level, k)), b2Vec2(g.X(level, b), g.Y(level, k)));
            break;
        case 2:
            add(b2Vec2(g.X(level, k), g.y0 - side), b2Vec2(g.X(level, k), g.y0 + 2.0f * side));
            break;
        default:
        {
            const int m = std::max(1, int(rng.Index(uint32_t(n))));
            add(b2Vec2(g.X(level, a), g.Y(level, k)),
                b2Vec2(g.X(level, a + m), g.Y(level, k + ((i & 4) ? m : -m))));
            break;
        }
        }
    }
    // Starting outside the grid: going in, passing by, staying outside, from and to the far bodies.
    for (int i = 0; i < 40; ++i)
    {
        const float t = rng.Uniform(-0.2f, 1.2f);
        const float gap = side * rng.Uniform(0.05f, 3.0f);
        b2Vec2 outside;
        switch (i % 4)
        {
        case 0:
            outside.Set(g.x0 - gap, g.y0 + t * side);
            break;
        case 1:
            outside.Set(g.x0 + side + gap, g.y0 + t * side);
            break;
        case 2:
            outside.Set(g.x0 + t * side, g.y0 - gap);
            break;
        default:
            outside.Set(g.x0 + t * side, g.y0 + side + gap);
            break;
        }
        switch ((i / 4) % 5)
        {
        case 0:
            add(outside, d.InGrid(0.0f));
            break;
        case 1:
            add(outside, outside + 2.0f * (d.InGrid(0.0f) - outside));
            break;
        case 2:
            add(outside, outside + side * rng.Uniform(0.1f, 1.0f) * direction());
            break;
        case 3:
            if (!p.farPoints.empty())
            {
                const b2Vec2 far = p.farPoints[rng.Index(uint32_t(p.farPoints.size()))];
                add(d.InGrid(0.0f), far + b2Vec2(rng.Uniform(-1.0f, 1.0f), rng.Uniform(-1.0f, 1.0f)));
            }
            else
            {
                add(outside, d.InGrid(side));
            }
            break;
        default:
            if (!p.farPoints.empty())
            {
                const b2Vec2 far = p.farPoints[rng.Index(uint32_t(p.farPoints.size()))];
                add(far + 5.0f * direction(),
                    far + b2Vec2(rng.Uniform(-0.5f, 0.5f), rng.Uniform(-0.5f, 0.5f)));
            }
            else
            {
                add(d.InGrid(side), outside);
            }
            break;
        }
    }
    // Along the edges of fat boxes, from their corners, and through fixtures' tight boxes.
    for (int i = 0; i < 30; ++i)
    {
        const Live& l = d.RandomLive();
        const b2AABB tight = l.fixture->GetAABB(l.child);
        const b2AABB fat = Fatten(tight);
        const float s = leaf * rng.Uniform(1.0f, 4.0f);
        switch (i % 5)
        {
        case 0:
            add(b2Vec2(fat.lowerBound.x - s, fat.upperBound.y),
                b2Vec2(fat.upperBound.x + s, fat.upperBound.y));
            break;
        case 1:
            add(b2Vec2(fat.lowerBound.x, fat.lowerBound.y - s),
                b2Vec2(fat.lowerBound.x, fat.upperBound.y + s));
            break;
        case 2:
            add(fat.upperBound, fat.upperBound + s * direction());
            break;
        case 3:
            add(b2Vec2(tight.lowerBound.x - s, tight.GetCenter().y),
                b2Vec2(tight.upperBound.x + s, tight.GetCenter().y));
            break;
        default:
            add(tight.GetCenter(), tight.GetCenter() + s * direction());
            break; // from inside a shape
        }
    }
    // Long rays from far outside, through the world and out again. Not much longer: from 1e6 m away (float
    // resolution 6 cm) b2CircleShape/b2PolygonShape::RayCast report spurious hits whose acceptance depends on
    // the clipped maxFraction, so the closest hit depends on the traversal order, in either build.
    for (int i = 0; i < 10; ++i)
    {
        const float y = g.y0 + side * rng.Uniform01();
        const float x = g.x0 + side * rng.Uniform01();
        const float lo = -4.0f * side, hi = 5.0f * side;
        if (i % 2 == 0)
        {
            add(b2Vec2(g.x0 + lo, y), b2Vec2(g.x0 + hi, y + rng.Uniform(-1.0f, 1.0f)));
        }
        else
        {
            add(b2Vec2(x + rng.Uniform(-1.0f, 1.0f), g.y0 + hi), b2Vec2(x, g.y0 + lo));
        }
    }
    // Some of the above again, reversed.
    const size_t before = rays.size();
    for (int i = 0; i < 20 && before > 0; ++i)
    {
        const Ray r = rays[rng.Index(uint32_t(before))];
        add(r.p2, r.p1);
    }
    while (int(rays.size()) < kRaysPerScene)
    {
        add(d.InGrid(0.2f * side), d.InGrid(0.2f * side));
    }
    return rays;
}

// --------------------------------------------------------------------------------------------------------

void PrintList(Out& out, const std::vector<std::string>& items)
{
    // 16 per line keeps diff hunks readable.
    for (size_t i = 0; i < items.size(); ++i)
    {
        out.Text() += (i % 16 == 0) ? "\n  " : " ";
        out.Text() += items[i];
    }
    out.Text() += "\n";
}

struct SceneCounts
{
    int nonEmptyQueries = 0;
    int hitRays = 0;
    int64_t queryResults = 0;
    int64_t rayHits = 0;
};

SceneCounts DumpQueries(b2World& world, const Names& names, const std::vector<Live>& live,
                        const std::vector<b2AABB>& queries, Out& out, const char* label)
{
    SceneCounts counts;
    std::map<FixtureId, int> children;
    for (const Live& l : live)
    {
        ++children[l.id];
    }
    for (size_t qi = 0; qi < queries.size(); ++qi)
    {
        const b2AABB& box = queries[qi];
        CollectQuery all(names);
        world.QueryAABB(&all, box);
        std::sort(all.found.begin(), all.found.end());
        FirstQuery first;
        world.QueryAABB(&first, box);

        out.Printf("aabb %d %s n %d first %d:", int(qi), Box(box).c_str(), int(all.found.size()),
                   first.calls);
        std::vector<std::string> items;
        for (const FixtureId& id : all.found)
        {
            items.push_back(Name(id));
        }
        PrintList(out, items);

        counts.queryResults += int64_t(all.found.size());
        counts.nonEmptyQueries += all.found.empty() ? 0 : 1;
        if (first.calls != (all.found.empty() ? 0 : 1))
        {
            Fail("%s aabb %d %s: stopping at the first fixture took %d calls, %d fixtures overlap", label,
                 int(qi), Box(box).c_str(), first.calls, int(all.found.size()));
        }
        // Every fixture child whose tight box overlaps must be reported (fat boxes contain tight ones); a
        // fixture is reported at most once per child.
        std::map<FixtureId, int> reported, expected;
        for (const FixtureId& id : all.found)
        {
            ++reported[id];
        }
        for (const Live& l : live)
        {
            if (b2TestOverlap(l.fixture->GetAABB(l.child), box))
            {
                ++expected[l.id];
            }
        }
        for (const auto& [id, n] : expected)
        {
            if (reported[id] < n)
            {
                Fail("%s aabb %d %s: fixture %s overlaps %d times, reported %d times", label, int(qi),
                     Box(box).c_str(), Name(id).c_str(), n, reported[id]);
            }
        }
        for (const auto& [id, n] : reported)
        {
            const auto child = children.find(id);
            const int childCount = child == children.end() ? 0 : child->second;
            if (n > childCount)
            {
                Fail("%s aabb %d %s: fixture %s (%d live children) reported %d times", label, int(qi),
                     Box(box).c_str(), Name(id).c_str(), childCount, n);
            }
        }
    }
    return counts;
}

// Does the segment cross `box` grown by `margin`? Liang-Barsky clipping in double precision.
bool SegmentCrosses(const Ray& ray, const b2AABB& box, double margin)
{
    const double p[2] = {double(ray.p1.x), double(ray.p1.y)};
    const double d[2] = {double(ray.p2.x) - p[0], double(ray.p2.y) - p[1]};
    const double lo[2] = {double(box.lowerBound.x) - margin, double(box.lowerBound.y) - margin};
    const double hi[2] = {double(box.upperBound.x) + margin, double(box.upperBound.y) + margin};
    double t0 = 0.0, t1 = 1.0;
    return qptest::ClipToSlabs(p, d, lo, hi, t0, t1);
}

void DumpRays(b2World& world, const Names& names, const std::vector<Live>& live, const std::vector<Ray>& rays,
              Out& out, const char* label, SceneCounts& counts)
{
    for (size_t ri = 0; ri < rays.size(); ++ri)
    {
        const Ray& ray = rays[ri];
        AllHits all(names);
        world.RayCast(&all, ray.p1, ray.p2);
        std::sort(all.hits.begin(), all.hits.end());
        ClosestHit closest(names, false);
        world.RayCast(&closest, ray.p1, ray.p2);
        ClosestHit odd(names, true);
        world.RayCast(&odd, ray.p1, ray.p2);
        AnyHit any;
        world.RayCast(&any, ray.p1, ray.p2);

        out.Printf("ray %d %s -> %s hits %d any %d", int(ri), V(ray.p1).c_str(), V(ray.p2).c_str(),
                   int(all.hits.size()), any.calls);
        if (closest.hit)
        {
            out.Printf(" closest %s %s", F(closest.best).c_str(), V(closest.bestPoint).c_str());
            if (closest.last != closest.best) // never with Box2D's clipping; shown so that a difference diffs
            {
                out.Printf(" last %s", F(closest.last).c_str());
            }
        }
        if (odd.hit)
        {
            out.Printf(" odd %s %s", F(odd.best).c_str(), V(odd.bestPoint).c_str());
            if (odd.last != odd.best)
            {
                out.Printf(" last %s", F(odd.last).c_str());
            }
        }
        out.Text() += ":";
        std::vector<std::string> items;
        for (const Hit& h : all.hits)
        {
            items.push_back(Name(h.id) + "@" + F(h.fraction) + V(h.point) + V(h.normal));
        }
        PrintList(out, items);

        counts.rayHits += int64_t(all.hits.size());
        counts.hitRays += all.hits.empty() ? 0 : 1;

        // Self-checks.
        const std::string where =
            std::string(label) + " ray " + std::to_string(ri) + " " + V(ray.p1) + " -> " + V(ray.p2);
        if (any.calls != (all.hits.empty() ? 0 : 1))
        {
            Fail("%s: terminating at the first hit took %d calls, %d hits", where.c_str(), any.calls,
                 int(all.hits.size()));
        }
        bool haveMin = false, haveOdd = false;
        float minAll = 0.0f, minOdd = 0.0f;
        for (const Hit& h : all.hits)
        {
            if (!haveMin || h.fraction < minAll)
            {
                haveMin = true;
                minAll = h.fraction;
            }
            if (h.id.body % 2 != 0 && (!haveOdd || h.fraction < minOdd))
            {
                haveOdd = true;
                minOdd = h.fraction;
            }
        }
        if (closest.hit != haveMin || (haveMin && closest.best != minAll))
        {
            Fail("%s: closest hit %d %s, minimum of all hits %d %s", where.c_str(), int(closest.hit),
                 F(closest.best).c_str(), int(haveMin), F(minAll).c_str());
        }
        if (closest.beyondClip != 0 || odd.beyondClip != 0)
        {
            Fail("%s: %d reports beyond the fraction the closest-hit callback had clipped the ray to (%d "
                 "with the "
                 "filter)",
                 where.c_str(), closest.beyondClip, odd.beyondClip);
        }
        if (odd.hit != haveOdd || (haveOdd && odd.best != minOdd))
        {
            Fail("%s: closest odd hit %d %s, minimum of odd hits %d %s", where.c_str(), int(odd.hit),
                 F(odd.best).c_str(), int(haveOdd), F(minOdd).c_str());
        }
        // Brute force: every fixture child's own ray cast. For long rays, b2CircleShape::RayCast (c^2 - rr b
        // in float) and b2PolygonShape::RayCast report hits far from the shape, which the broadphase rightly
        // prunes: so the world's hits must be a subset of the brute-force ones, and must include every
        // brute-force hit of a fixture whose tight box the segment really crosses (in double precision, box
        // grown by 1 cm).
        std::vector<Hit> brute, credible;
        b2RayCastInput input;
        input.p1 = ray.p1;
        input.p2 = ray.p2;
        input.maxFraction = 1.0f;
        for (const Live& l : live)
        {
            b2RayCastOutput output;
            if (l.fixture->RayCast(&output, input, l.child))
            {
                const float f = output.fraction;
                const b2Vec2 point = (1.0f - f) * input.p1 + f * input.p2;
                brute.push_back({l.id, f, point, output.normal});
                if (SegmentCrosses(ray, l.fixture->GetAABB(l.child), 0.01))
                {
                    credible.push_back(brute.back());
                }
            }
        }
        std::sort(brute.begin(), brute.end());
        std::sort(credible.begin(), credible.end());
        std::vector<Hit> onlyBrute, onlyWorld;
        std::set_difference(credible.begin(), credible.end(), all.hits.begin(), all.hits.end(),
                            std::back_inserter(onlyBrute));
        std::set_difference(all.hits.begin(), all.hits.end(), brute.begin(), brute.end(),
                            std::back_inserter(onlyWorld));
        if (!onlyBrute.empty() || !onlyWorld.empty())
        {
            std::string diff;
            for (const Hit& h : onlyBrute)
            {
                diff += " missing " + Name(h.id) + "@" + F(h.fraction) + V(h.point);
            }
            for (const Hit& h : onlyWorld)
            {
                diff += " extra " + Name(h.id) + "@" + F(h.fraction) + V(h.point);
            }
            Fail("%s: %d hits; a brute-force ray cast of every fixture finds %d, %d of them on fixtures the "
                 "segment "
                 "crosses;%s",
                 where.c_str(), int(all.hits.size()), int(brute.size()), int(credible.size()),
                 diff.substr(0, 400).c_str());
        }
    }
}

bool RunCase(const Case& c, bool validate, bool grid, Out& out)
{
    const auto start = std::chrono::steady_clock::now();
    const char* name = quadphase::scenes::SceneName(c.id);
    quadphase::scenes::Scene scene = quadphase::scenes::BuildScene(c.id, c.size, c.seed);
    b2World& world = *scene.world;
    const Prepared p = Prepare(scene, c.seed, validate, grid);

    int32_t contacts = 0, touching = 0;
    for (b2Contact* ct = world.GetContactList(); ct != nullptr; ct = ct->GetNext())
    {
        ++contacts;
        touching += ct->IsTouching() ? 1 : 0;
    }
    const Names names(world);
    const std::vector<Live> live = LiveChildren(names);

    out.Printf("# scene %s size %d seed %u\n", name, c.size, unsigned(c.seed));
    out.Printf("world bodies %d fixtures %d proxies %d disabled %d destroyed %d contacts %d touching %d\n",
               int(world.GetBodyCount()), int(names.All().size()), int(world.GetProxyCount()), p.disabled,
               p.destroyed, int(contacts), int(touching));
    out.Printf("region %s grid %s %s side %s depth %d far %d\n", Box(p.region).c_str(), F(p.grid.x0).c_str(),
               F(p.grid.y0).c_str(), F(p.grid.side).c_str(), p.grid.depth, int(p.farPoints.size()));

    Rng rng(c.seed ^ 0x9e3779b9u);
    const std::vector<b2AABB> queries = MakeQueries(p, live, rng);
    const std::vector<Ray> rays = MakeRays(p, live, rng);
    char label[64];
    std::snprintf(label, sizeof(label), "%s/%d/%u", name, c.size, unsigned(c.seed));
    SceneCounts counts = DumpQueries(world, names, live, queries, out, label);
    DumpRays(world, names, live, rays, out, label, counts);

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(
        stderr,
        "qp_query_dump: %-9s %5d seed %u: %d fixtures, %d contacts; %d/%d boxes found something (%" PRId64
        " results), %d/%d rays hit (%" PRId64 " hits); %.2f s\n",
        name, c.size, unsigned(c.seed), int(names.All().size()), int(contacts), counts.nonEmptyQueries,
        int(queries.size()), counts.queryResults, counts.hitRays, int(rays.size()), counts.rayHits, seconds);

    // Not trivially empty: a good part of the boxes and rays must find something, and not everything. A quarter,
    // not a third: where the bodies end up differs between targets (fused multiply-adds on ARM64, and the order
    // GCC evaluates the two random draws of one b2Vec2 in), and mixed/1000/11's rays hit 103 of 300 on x86-64 but
    // 95 on ARM64.
    if (counts.nonEmptyQueries < int(queries.size()) / 4 || counts.nonEmptyQueries == int(queries.size()))
    {
        Fail("%s: %d of %d boxes found something (want at least a quarter, and not all)", label,
             counts.nonEmptyQueries, int(queries.size()));
    }
    if (counts.hitRays < int(rays.size()) / 4 || counts.hitRays == int(rays.size()))
    {
        Fail("%s: %d of %d rays hit something (want at least a quarter, and not all)", label, counts.hitRays,
             int(rays.size()));
    }
    if (contacts == 0 || p.farPoints.empty())
    {
        Fail("%s: %d contacts, %d far bodies (want some of each)", label, int(contacts),
             int(p.farPoints.size()));
    }

#if QUADPHASE_VARIANT_QUADPHASE
    const quadphase::Stats stats = quadphase::GetStats(world);
    std::fprintf(stderr,
                 "qp_query_dump:   quadtree depth %d bounds [%g %g %g %g] leaf %g, %d proxies outside\n",
                 stats.depth, double(stats.bounds.minX), double(stats.bounds.minY), double(stats.bounds.maxX),
                 double(stats.bounds.maxY), double(stats.leafSize), int(stats.outsideCount));
    if (grid &&
        (stats.depth != p.grid.depth || stats.bounds.minX != p.grid.x0 || stats.bounds.minY != p.grid.y0 ||
         stats.bounds.maxX != p.grid.x0 + p.grid.side || stats.bounds.maxY != p.grid.y0 + p.grid.side))
    {
        Fail("%s: --grid: the quadtree is not on the query grid", label);
    }
    if (validate)
    {
        const quadphase::ValidationReport report = quadphase::GetValidationReport(world);
        std::fprintf(stderr,
                     "qp_query_dump:   validation: %" PRId64 " checks, %" PRId64 " pairs, %" PRId64
                     " mismatches\n",
                     report.checks, report.pairsCompared, report.mismatches);
        if (report.mismatches != 0 || report.checks == 0)
        {
            Fail("%s: validation: %" PRId64 " checks, %" PRId64 " mismatches; first: %s", label,
                 report.checks, report.mismatches, report.firstMismatch.c_str());
        }
    }
#endif
    return true;
}

} // namespace

int main(int argc, char** argv)
{
    const char* path = nullptr;
    bool validate = false;
    bool grid = false;
    for (int i = 1; i < argc; ++i)
    {
        if (std::strcmp(argv[i], "--validate") == 0)
        {
            validate = true;
        }
        else if (std::strcmp(argv[i], "--grid") == 0)
        {
            grid = true;
        }
        else if (path == nullptr && argv[i][0] != '-')
        {
            path = argv[i];
        }
        else
        {
            path = nullptr;
            break;
        }
    }
#if !QUADPHASE_VARIANT_QUADPHASE
    if (validate || grid)
    {
        std::fprintf(stderr, "qp_query_dump: --validate and --grid need the quadphase build\n");
        return 2;
    }
#endif
    if (path == nullptr)
    {
        std::fprintf(stderr, "usage: %s <output file> [--validate] [--grid]\n", argv[0]);
        return 2;
    }

    // Every scene is covered.
    for (const quadphase::scenes::SceneInfo& info : quadphase::scenes::AllScenes())
    {
        bool covered = false;
        for (const Case& c : kCases)
        {
            covered = covered || c.id == info.id;
        }
        if (!covered)
        {
            Fail("scene %s has no case in kCases", info.name);
        }
    }

    Out out;
#if QUADPHASE_VARIANT_QUADPHASE
    std::fprintf(stderr, "qp_query_dump: quadphase build%s%s\n", validate ? ", validation on" : "",
                 grid ? ", quadtree on the query grid" : "");
#else
    std::fprintf(stderr, "qp_query_dump: stock build\n");
#endif
    for (const Case& c : kCases)
    {
        RunCase(c, validate, grid, out);
    }

    std::FILE* file = std::fopen(path, "wb");
    if (file == nullptr || std::fwrite(out.Text().data(), 1, out.Text().size(), file) != out.Text().size() ||
        std::fclose(file) != 0)
    {
        std::fprintf(stderr, "qp_query_dump: cannot write %s\n", path);
        return 2;
    }
    std::fprintf(stderr, "qp_query_dump: wrote %zu bytes to %s\n", out.Text().size(), path);
    if (g_failures > 0)
    {
        std::fprintf(stderr, "qp_query_dump: %d self-check failures\n", g_failures);
        return 1;
    }
    return 0;
}
