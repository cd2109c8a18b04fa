// SPDX-License-Identifier: MIT
// qp-query-stock / qp-query-quadtree: QueryAABB, ray casts and a mass SetTransform through b2World. One
// source, compiled against stock Box2D 2.4.1 and against Box2D with the quadtree (box2d_variant.h);
// bench/bench.py runs the two alternately, in a new random order every round, and takes medians over the
// rounds.
//
//   qp-query-<variant> [--bodies 50000] [--world 1000] [--queries 2000] [--query-size 2] [--short-rays 2000]
//                      [--short-length 10] [--long-rays 200] [--teleport 37500] [--teleport-queries 2000]
//                      [--repeats 3] [--seed 1] [--threads T|default] [--json FILE] [--label TEXT]
//
// The world: no gravity, --bodies sleeping dynamic bodies, one box each (half sides 0.25-1 m, random angle)
// at uniform random positions over a --world metres square, stepped once so that both builds start from a
// world whose broadphase has no pending move. Fixture user data = the body's index (its id in the hashes).
//
// Workloads, each timed as a whole (one clock-read pair around all its queries), --repeats times in a row:
//   aabb_small          --queries QueryAABBs, squares of side --query-size at random centres, every hit kept;
//   ray_short_{all,closest}  --short-rays rays of --short-length m from random points in random directions;
//   ray_axis_{all,closest}   --long-rays rays across the whole world, half horizontal, half vertical;
//   ray_diag_{all,closest}   --long-rays rays from one corner's side to the opposite corner, both diagonals;
//   teleport            SetTransform of --teleport bodies to random positions, then --teleport-queries small
//                       QueryAABBs, timed together (stock moves its tree in SetTransform; a queue pays
//                       later);
//   teleport_step       the b2World::Step after it (the new pairs of the moved proxies), timed alone; its
//   "hits"
//                       are the world's contacts after the last repeat's step.
// "all" callbacks return 1 (every fixture the ray touches); "closest" ones return the hit's fraction (Box2D's
// closest-hit idiom: the ray is clipped as it goes).
//   <workload>_floor    for aabb_small and the three "all" ray workloads: the output alone. The proxies the
//                       build's broadphase hands b2World for each query are recorded once (untimed); the
//                       floor times only what b2World and the user callback then do with them (b2_world.cpp's
//                       wrapper code, less GetUserData). No broadphase reports those proxies for less, so
//                       stock's time over the floor bounds what any broadphase can gain there.
//
// Exactness: after the timed loop, each query's hits are sorted by fixture id and hashed (FNV-1a 64); a
// closest-hit ray is hashed as (fixture id or -1, fraction's bits). A workload's hash combines its queries'
// hashes in order, over every repeat; bench.py checks that both builds give the same hash and hit count for
// every workload.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "box2d_variant.h"
#include "tool_common.h"

namespace
{

using namespace qpbench;

struct Hits
{
    std::vector<uint64_t> ids;     // every query's hits, one after the other
    std::vector<size_t> ends;      // end of each query's hits in ids
    std::vector<uint64_t> closest; // closest-hit rays: (id + 1) << 32 | fraction bits
};

uint64_t FixtureId(b2Fixture* f)
{
    return uint64_t(f->GetUserData().pointer);
}

class AllQuery : public b2QueryCallback, public b2RayCastCallback
{
public:
    explicit AllQuery(Hits& hits) : m_hits(hits) {}
    bool ReportFixture(b2Fixture* f) override
    {
        m_hits.ids.push_back(FixtureId(f));
        return true;
    }
    float ReportFixture(b2Fixture* f, const b2Vec2&, const b2Vec2&, float) override
    {
        m_hits.ids.push_back(FixtureId(f));
        return 1.0f;
    }

private:
    Hits& m_hits;
};

class ClosestRay : public b2RayCastCallback
{
public:
    float ReportFixture(b2Fixture* f, const b2Vec2&, const b2Vec2&, float fraction) override
    {
        id = int64_t(FixtureId(f));
        this->fraction = fraction;
        return fraction;
    }
    int64_t id = -1;
    float fraction = 1.0f;
};

struct Ray
{
    b2Vec2 p1, p2;
};

/// The fixture proxies a broadphase reports for each of a list of queries, in its order (see Bench::Record).
struct Candidates
{
    std::vector<const b2FixtureProxy*> proxies; // every query's, one after the other
    std::vector<size_t> ends;                   // end of each query's proxies
};

/// Records what b2BroadPhase::Query and RayCast report, for the floors. Never clips a ray: the "all"
/// callbacks do not either (they return 1), so the candidates are those of the timed casts.
class Recorder
{
public:
    Recorder(const b2BroadPhase& broadPhase, Candidates& out) : m_broadPhase(broadPhase), m_out(out) {}
    bool QueryCallback(int32 id)
    {
        Add(id);
        return true;
    }
    float RayCastCallback(const b2RayCastInput& input, int32 id)
    {
        Add(id);
        return input.maxFraction;
    }

private:
    void Add(int32 id)
    {
        m_out.proxies.push_back(static_cast<const b2FixtureProxy*>(m_broadPhase.GetUserData(id)));
    }
    const b2BroadPhase& m_broadPhase;
    Candidates& m_out;
};

struct Workload
{
    std::string name;
    std::vector<int64_t> ns; // per repeat
    Hits hits;               // over every repeat
    int64_t queries = 0;     // per repeat
    int64_t contacts = -1;   // teleport_step: the world's contacts after the last step (its "hits")
};

/// The hits' hash (see the top of the file), as 16 hex digits.
std::string HashHits(const Hits& hits)
{
    std::vector<uint64_t> perQuery;
    size_t begin = 0;
    for (size_t end : hits.ends)
    {
        std::vector<uint64_t> ids(hits.ids.begin() + long(begin), hits.ids.begin() + long(end));
        std::sort(ids.begin(), ids.end());
        perQuery.push_back(Fnv1a64(ids));
        begin = end;
    }
    perQuery.insert(perQuery.end(), hits.closest.begin(), hits.closest.end());
    char hex[24];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(Fnv1a64(perQuery)));
    return hex;
}

class Bench
{
public:
    Bench(const Args& args, uint32_t seed) : m_rng(seed), m_world(b2Vec2(0.0f, 0.0f))
    {
        m_size = float(args.GetInt("world", 1000));
        const long bodies = args.GetInt("bodies", 50000);
        std::uniform_real_distribution<float> half(0.25f, 1.0f), angle(0.0f, b2_pi);
        for (long i = 0; i < bodies; ++i)
        {
            b2BodyDef bd;
            bd.type = b2_dynamicBody;
            bd.awake = false;
            bd.position = Point();
            m_bodies.push_back(m_world.CreateBody(&bd));
            b2PolygonShape box;
            box.SetAsBox(half(m_rng), half(m_rng), b2Vec2(0.0f, 0.0f), angle(m_rng));
            b2FixtureDef fd;
            fd.shape = &box;
            fd.density = 1.0f;
            fd.userData.pointer = uintptr_t(i);
            m_bodies.back()->CreateFixture(&fd);
        }
        m_world.Step(1.0f / 60.0f, 8, 3);
    }

    b2World& World() { return m_world; }

    b2Vec2 Point()
    {
        std::uniform_real_distribution<float> u(0.0f, m_size);
        return b2Vec2(u(m_rng), u(m_rng));
    }

    std::vector<b2AABB> Boxes(long n, float side)
    {
        std::vector<b2AABB> boxes(size_t(std::max(0L, n)));
        for (b2AABB& b : boxes)
        {
            const b2Vec2 c = Point();
            b.lowerBound = c - b2Vec2(0.5f * side, 0.5f * side);
            b.upperBound = c + b2Vec2(0.5f * side, 0.5f * side);
        }
        return boxes;
    }

    std::vector<Ray> ShortRays(long n, float length)
    {
        std::uniform_real_distribution<float> angle(0.0f, 2.0f * b2_pi);
        std::vector<Ray> rays(size_t(std::max(0L, n)));
        for (Ray& r : rays)
        {
            const float a = angle(m_rng);
            r.p1 = Point();
            r.p2 = r.p1 + length * b2Vec2(std::cos(a), std::sin(a));
        }
        return rays;
    }

    /// Rays across the whole world, 1 m beyond its edges: horizontal and vertical (axis) or corner to corner,
    /// alternating the two diagonals and both directions (diagonal); offsets along the edge up to 5% of the
    /// side.
    std::vector<Ray> LongRays(long n, bool diagonal)
    {
        std::uniform_real_distribution<float> along(0.0f, m_size), offset(0.0f, 0.05f * m_size);
        const float lo = -1.0f, hi = m_size + 1.0f;
        std::vector<Ray> rays(size_t(std::max(0L, n)));
        for (size_t i = 0; i < rays.size(); ++i)
        {
            Ray& r = rays[i];
            if (!diagonal)
            {
                const float t = along(m_rng);
                r = i % 2 == 0 ? Ray{b2Vec2(lo, t), b2Vec2(hi, t)} : Ray{b2Vec2(t, lo), b2Vec2(t, hi)};
            }
            else
            {
                const float o = offset(m_rng);
                r = i % 2 == 0 ? Ray{b2Vec2(lo, lo + o), b2Vec2(hi, hi - o)}
                               : Ray{b2Vec2(lo, hi - o), b2Vec2(hi, lo + o)};
            }
            if (i % 4 >= 2)
            {
                std::swap(r.p1, r.p2);
            }
        }
        return rays;
    }

    void Query(const std::vector<b2AABB>& boxes, Hits& hits)
    {
        AllQuery callback(hits);
        for (const b2AABB& b : boxes)
        {
            m_world.QueryAABB(&callback, b);
            hits.ends.push_back(hits.ids.size());
        }
    }

    void Cast(const std::vector<Ray>& rays, bool closest, Hits& hits)
    {
        AllQuery all(hits);
        for (const Ray& r : rays)
        {
            if (closest)
            {
                ClosestRay callback;
                m_world.RayCast(&callback, r.p1, r.p2);
                uint32_t bits = 0;
                std::memcpy(&bits, &callback.fraction, sizeof bits);
                hits.closest.push_back((uint64_t(callback.id + 1) << 32) | bits);
            }
            else
            {
                m_world.RayCast(&all, r.p1, r.p2);
                hits.ends.push_back(hits.ids.size());
            }
        }
    }

    /// The candidates of each box (rays null) or each ray, from the world's own broadphase.
    Candidates Record(const std::vector<b2AABB>& boxes, const std::vector<Ray>* rays) const
    {
        Candidates c;
        const b2BroadPhase& bp = m_world.GetContactManager().m_broadPhase;
        Recorder recorder(bp, c);
        for (size_t i = 0; i < (rays != nullptr ? rays->size() : boxes.size()); ++i)
        {
            if (rays != nullptr)
            {
                bp.RayCast(&recorder, b2RayCastInput{(*rays)[i].p1, (*rays)[i].p2, 1.0f});
            }
            else
            {
                bp.Query(&recorder, boxes[i]);
            }
            c.ends.push_back(c.proxies.size());
        }
        return c;
    }

    /// The floor of Query (rays null) or of Cast(rays, false): b2World::QueryAABB's or RayCast's per-proxy work
    /// (b2WorldQueryWrapper or b2WorldRayCastWrapper, less GetUserData) and the callback, over the recorded
    /// candidates.
    static void Floor(const std::vector<Ray>* rays, const Candidates& c, Hits& hits)
    {
        AllQuery callback(hits);
        size_t begin = 0;
        for (size_t q = 0; q < c.ends.size(); ++q)
        {
            for (size_t i = begin; i < c.ends[q]; ++i)
            {
                b2Fixture* fixture = c.proxies[i]->fixture;
                if (rays == nullptr)
                {
                    callback.ReportFixture(fixture);
                    continue;
                }
                const b2RayCastInput input{(*rays)[q].p1, (*rays)[q].p2, 1.0f};
                b2RayCastOutput output;
                if (fixture->RayCast(&output, input, c.proxies[i]->childIndex))
                {
                    const float fraction = output.fraction;
                    const b2Vec2 point = (1.0f - fraction) * input.p1 + fraction * input.p2;
                    callback.ReportFixture(fixture, point, output.normal, fraction);
                }
            }
            hits.ends.push_back(hits.ids.size());
            begin = c.ends[q];
        }
    }

    /// SetTransform of the bodies TeleportPlan chose to the places it drew.
    void Teleport(const std::vector<int32_t>& which, const std::vector<b2Transform>& to)
    {
        for (size_t i = 0; i < which.size(); ++i)
        {
            m_bodies[size_t(which[i])]->SetTransform(to[i].p, to[i].q.GetAngle());
        }
    }

    /// `count` bodies (a random choice, new each call) and random positions and angles for them.
    void TeleportPlan(long count, std::vector<int32_t>& which, std::vector<b2Transform>& to)
    {
        which.resize(m_bodies.size());
        std::iota(which.begin(), which.end(), 0);
        std::shuffle(which.begin(), which.end(), m_rng);
        which.resize(size_t(std::min<long>(count, long(which.size()))));
        std::uniform_real_distribution<float> angle(0.0f, b2_pi);
        to.resize(which.size());
        for (b2Transform& t : to)
        {
            t.Set(Point(), angle(m_rng));
        }
    }

private:
    std::mt19937 m_rng;
    b2World m_world;
    float m_size = 1000.0f;
    std::vector<b2Body*> m_bodies;
};

} // namespace

int main(int argc, char** argv)
{
    const Args args(argc, argv, "qp-query-" + std::string(kVariant),
                    {"bodies", "world", "queries", "query-size", "short-rays", "short-length", "long-rays",
                     "teleport", "teleport-queries", "repeats", "seed", "threads", "json", "label"});
    const long repeats = args.GetInt("repeats", 3);
    args.Check(repeats >= 1 && args.GetInt("bodies", 50000) >= 1 && args.GetInt("world", 1000) > 0,
               "usage: qp-query-%s [--bodies 50000] [--world 1000] [--queries 2000] [--query-size 2]\n"
               "       [--short-rays 2000] [--short-length 10] [--long-rays 200] [--teleport 37500]\n"
               "       [--teleport-queries 2000] [--repeats 3 (>= 1)] [--seed 1] [--threads T|default]\n"
               "       [--json FILE] [--label TEXT]\n",
               kVariant);
    const uint32_t seed = uint32_t(args.GetInt("seed", 1));
    const int64_t setup0 = NowNs();
    Bench bench(args, seed);
    ApplyThreads(bench.World(), args.Get("threads", "default"));
    const double setupSeconds = double(NowNs() - setup0) * 1e-9;

    // The inputs are drawn once, before any timing, in the same order in both builds.
    const float querySide = float(args.GetInt("query-size", 2));
    const std::vector<b2AABB> boxes = bench.Boxes(args.GetInt("queries", 2000), querySide);
    const std::vector<Ray> shortRays =
        bench.ShortRays(args.GetInt("short-rays", 2000), float(args.GetInt("short-length", 10)));
    const std::vector<Ray> axisRays = bench.LongRays(args.GetInt("long-rays", 200), false);
    const std::vector<Ray> diagRays = bench.LongRays(args.GetInt("long-rays", 200), true);
    const std::vector<b2AABB> teleportBoxes = bench.Boxes(args.GetInt("teleport-queries", 2000), querySide);

    std::vector<Workload> work;
    auto run = [&](const char* name, int64_t queries, auto&& body) {
        work.push_back(Workload{name, {}, {}, queries});
        Workload& w = work.back();
        for (long r = 0; r < repeats; ++r)
        {
            const int64_t t0 = NowNs();
            body(w.hits);
            w.ns.push_back(NowNs() - t0);
        }
    };
    run("aabb_small", int64_t(boxes.size()), [&](Hits& h) { bench.Query(boxes, h); });
    run("ray_short_all", int64_t(shortRays.size()), [&](Hits& h) { bench.Cast(shortRays, false, h); });
    run("ray_short_closest", int64_t(shortRays.size()), [&](Hits& h) { bench.Cast(shortRays, true, h); });
    run("ray_axis_all", int64_t(axisRays.size()), [&](Hits& h) { bench.Cast(axisRays, false, h); });
    run("ray_axis_closest", int64_t(axisRays.size()), [&](Hits& h) { bench.Cast(axisRays, true, h); });
    run("ray_diag_all", int64_t(diagRays.size()), [&](Hits& h) { bench.Cast(diagRays, false, h); });
    run("ray_diag_closest", int64_t(diagRays.size()), [&](Hits& h) { bench.Cast(diagRays, true, h); });

    // The floors (after the workloads, before the teleport moves anything): candidates recorded untimed, then
    // timed like the workloads. Each must give its workload's hits, or it is not that workload's output.
    const auto floor = [&](const std::string& of, const std::vector<Ray>* rays) {
        const Candidates c = bench.Record(boxes, rays);
        run((of + "_floor").c_str(), int64_t(c.ends.size()), [&](Hits& h) { Bench::Floor(rays, c, h); });
        const auto w =
            std::find_if(work.begin(), work.end(), [&](const Workload& x) { return x.name == of; });
        if (HashHits(w->hits) != HashHits(work.back().hits))
        {
            Die(3, "qp-query: %s_floor does not give the hits of %s\n", of.c_str(), of.c_str());
        }
    };
    floor("aabb_small", nullptr);
    floor("ray_short_all", &shortRays);
    floor("ray_axis_all", &axisRays);
    floor("ray_diag_all", &diagRays);

    // Teleport: a new random choice of bodies and places per repeat (drawn before its clock starts), then the
    // step.
    work.push_back(Workload{"teleport", {}, {}, int64_t(teleportBoxes.size())});
    work.push_back(Workload{"teleport_step", {}, {}, 1});
    const long teleport = args.GetInt("teleport", 37500);
    std::vector<int32_t> which;
    std::vector<b2Transform> to;
    for (long r = 0; r < repeats; ++r)
    {
        Workload& w = work[work.size() - 2];
        bench.TeleportPlan(teleport, which, to);
        int64_t t0 = NowNs();
        bench.Teleport(which, to);
        bench.Query(teleportBoxes, w.hits);
        w.ns.push_back(NowNs() - t0);
        t0 = NowNs();
        bench.World().Step(1.0f / 60.0f, 8, 3);
        work.back().ns.push_back(NowNs() - t0);
        work.back().contacts = bench.World().GetContactCount();
        work.back().hits.ids.push_back(uint64_t(work.back().contacts));
        work.back().hits.ends.push_back(work.back().hits.ids.size());
    }

    JsonLine j;
    j.Str("tool", "qp-query")
        .Str("variant", kVariant)
        .Str("label", args.Get("label"))
        .Str("threads_arg", args.Get("threads", "default"))
        .Int("omp_num_threads", OmpNumThreadsEnv())
        .Int("bodies", args.GetInt("bodies", 50000))
        .Int("world_m", args.GetInt("world", 1000))
        .Int("repeats", repeats)
        .Int("seed", seed)
        .Int("teleported", teleport)
        .Num("setup_s", setupSeconds)
        .Int("peak_rss_bytes", PeakRss());
    for (const Workload& w : work)
    {
        const std::string k = w.name;
        // Fixtures reported (all-hit callbacks) or rays that hit something (closest-hit), per repeat.
        const auto rayHits = std::count_if(w.hits.closest.begin(), w.hits.closest.end(),
                                           [](uint64_t c) { return c >> 32 != 0; });
        const double hits = double(int64_t(w.hits.ids.size()) + rayHits) / double(repeats);
        j.Num((k + "_ns").c_str(), double(Median(w.ns)))
            .Int((k + "_queries").c_str(), w.queries)
            .Num((k + "_hits").c_str(), w.contacts >= 0 ? double(w.contacts) : hits)
            .Str((k + "_hash").c_str(), HashHits(w.hits));
        std::printf("%s %-18s %10.3f ms (median of %ld), %lld queries\n", kVariant, w.name.c_str(),
                    double(Median(w.ns)) * 1e-6, repeats, static_cast<long long>(w.queries));
    }
    AppendLine(args.Get("json"), j.Text());
    return 0;
}
