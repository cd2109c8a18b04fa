// SPDX-License-Identifier: MIT
// A Box2D 2.4.1 program that knows nothing of quadphase: compiled against stock Box2D's pristine headers and linked
// to the stock shared library, then run again on quadphase's libbox2d.so.2 through LD_LIBRARY_PATH
// (tests/abi/RunSwapProbe.cmake). It prints, line by line, what must not depend on the library:
// - "library <path> <kind>": the libbox2d it runs on (dladdr of a Box2D function) and whether quadphase's symbols
//   are in the process (dlsym), so a run proves which library it used;
// - "sensors step N ...": the contact set after every step of a scene of sensors moving on fixed paths (their
//   motion does not depend on the contacts, so both libraries must give the same contacts at every step), read
//   through stock's inline b2World::GetContactList and GetContactCount;
// - "sensors queries ...": QueryAABB and RayCast hits in that scene (sets, and the closest hit);
// - a pile of boxes, whose contacts are not compared (the pair order steers the solver, so the two runs diverge):
//   with QUADPHASE_VALIDATE=1 the quadphase run checks every UpdatePairs against a shadow tree instead;
// - "inline ...": stock's inline b2BroadPhase functions compiled into this program (GetUserData, GetFatAABB,
//   TestOverlap, GetProxyCount, GetTreeHeight) read valid values on either library;
// - "templates ...": stock's inline UpdatePairs, Query and RayCast templates and tree statistics on a b2BroadPhase
//   of the program's own (stock's answers on quadphase's library with QUADPHASE_STOCK_TREE=1 only);
// - "edges ...": those inline readers right after CreateProxy, MoveProxy, TouchProxy, DestroyProxy and ShiftOrigin
//   (through b2Body and b2World calls), before any Step: they must read what stock's tree holds at that moment.
// Exit status 1 when an inline check fails. Built twice: as is, and with -O0 -fno-inline -rdynamic, which puts
// out-of-line copies of stock's inline functions in the executable's dynamic symbol table (the interposition probe).
#include <box2d/box2d.h>

#include <dlfcn.h>

#include <algorithm>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <vector>

namespace
{

int g_failures = 0;

void Check(bool ok, const char* what, long detail)
{
    if (!ok)
    {
        if (++g_failures <= 20)
        {
            std::printf("inline check failed: %s (%ld)\n", what, detail);
        }
    }
}

// FNV-1a over a sequence of 64-bit values.
struct Hash
{
    uint64_t value = 1469598103934665603ull;
    void Add(uint64_t v)
    {
        for (int i = 0; i < 8; ++i)
        {
            value ^= (v >> (8 * i)) & 0xffu;
            value *= 1099511628211ull;
        }
    }
    // Sorts `ids` and adds them in that order.
    template <typename T>
    void AddSorted(std::vector<T>& ids)
    {
        std::sort(ids.begin(), ids.end());
        for (const T id : ids)
        {
            Add(uint64_t(id));
        }
    }
    // One call's hits as a set: AddSorted, then a separator.
    template <typename T>
    void AddSet(std::vector<T>& ids)
    {
        AddSorted(ids);
        Add(~uint64_t(0));
    }
};

uint64_t Index(b2Fixture* f)
{
    return static_cast<uint64_t>(f->GetUserData().pointer);
}

// The contact set, sorted: (fixture index A, fixture index B, touching), A < B.
std::vector<std::pair<std::pair<uint64_t, uint64_t>, int>> Contacts(b2World& world)
{
    std::vector<std::pair<std::pair<uint64_t, uint64_t>, int>> out;
    for (b2Contact* c = world.GetContactList(); c != nullptr; c = c->GetNext())
    {
        uint64_t a = Index(c->GetFixtureA());
        uint64_t b = Index(c->GetFixtureB());
        if (a > b)
        {
            std::swap(a, b);
        }
        out.push_back(std::make_pair(std::make_pair(a, b), c->IsTouching() ? 1 : 0));
    }
    std::sort(out.begin(), out.end());
    return out;
}

void PrintContacts(const char* scene, int step, b2World& world)
{
    const std::vector<std::pair<std::pair<uint64_t, uint64_t>, int>> contacts = Contacts(world);
    Hash h;
    int touching = 0;
    for (size_t i = 0; i < contacts.size(); ++i)
    {
        h.Add(contacts[i].first.first);
        h.Add(contacts[i].first.second);
        h.Add(uint64_t(contacts[i].second));
        touching += contacts[i].second;
    }
    // GetContactCount is inline in b2_world.h: it reads b2ContactManager::m_contactCount at stock's offset.
    std::printf("%s step %d contacts %d listed %zu touching %d hash %016" PRIx64 "\n", scene, step,
                world.GetContactCount(), contacts.size(), touching, h.value);
}

// Stock's inline b2BroadPhase functions, compiled into this program, on every proxy of the world. A game cannot
// reach b2Fixture's proxy ids (protected), but the broadphase's user data is the public b2FixtureProxy, so the ids
// are found by asking GetUserData for ids from 0 up until every proxy has been seen (stock's tree numbers its inner
// nodes among the proxies, with null user data; this world never destroys a proxy, so no id is stale).
void CheckInline(const char* scene, b2World& world, bool containment = true)
{
    const b2BroadPhase& bp = world.GetContactManager().m_broadPhase;
    int32 expected = 0;
    for (b2Body* b = world.GetBodyList(); b != nullptr; b = b->GetNext())
    {
        for (b2Fixture* f = b->GetFixtureList(); f != nullptr; f = f->GetNext())
        {
            expected += f->GetShape()->GetChildCount();
        }
    }
    Check(bp.GetProxyCount() == expected, "GetProxyCount counts the fixtures' children", bp.GetProxyCount());
    Check(world.GetProxyCount() == expected, "b2World::GetProxyCount counts them", world.GetProxyCount());
    std::vector<std::pair<std::pair<const b2Fixture*, int32>, int32>> idOf; // (fixture, child) -> proxy id
    for (int32 id = 0; int32(idOf.size()) < expected && id < 4 * expected + 16; ++id)
    {
        const b2FixtureProxy* proxy = static_cast<const b2FixtureProxy*>(bp.GetUserData(id));
        if (proxy == nullptr)
        {
            continue;
        }
        Check(proxy->proxyId == id, "GetUserData gives the proxy of that id", id);
        const b2AABB& fat = bp.GetFatAABB(id);
        // (b2World::ShiftOrigin leaves the fixture proxies' own AABBs of sleeping bodies unshifted until they move.)
        Check(!containment || fat.Contains(proxy->aabb), "the fat AABB contains the fixture's AABB", id);
        Check(bp.TestOverlap(id, id), "a fat AABB overlaps itself", id);
        idOf.push_back(std::make_pair(std::make_pair(proxy->fixture, proxy->childIndex), id));
    }
    Check(int32(idOf.size()) == expected, "every proxy is found through GetUserData", long(idOf.size()));
    std::sort(idOf.begin(), idOf.end());
    const int32 height = bp.GetTreeHeight();
    Check(height >= 0 && height < 64, "GetTreeHeight is a height", height);
    // Contacts whose fixtures' fat AABBs overlap (the others are destroyed by the next Collide). Both libraries
    // agree, since the fat AABBs are the same bits: printed, and compared across the two runs for the sensors.
    int overlapping = 0;
    for (b2Contact* c = world.GetContactList(); c != nullptr; c = c->GetNext())
    {
        const std::pair<const b2Fixture*, int32> ka(c->GetFixtureA(), c->GetChildIndexA());
        const std::pair<const b2Fixture*, int32> kb(c->GetFixtureB(), c->GetChildIndexB());
        std::vector<std::pair<std::pair<const b2Fixture*, int32>, int32>>::const_iterator a =
            std::lower_bound(idOf.begin(), idOf.end(), std::make_pair(ka, int32(-1)));
        std::vector<std::pair<std::pair<const b2Fixture*, int32>, int32>>::const_iterator b =
            std::lower_bound(idOf.begin(), idOf.end(), std::make_pair(kb, int32(-1)));
        if (a == idOf.end() || b == idOf.end() || a->first != ka || b->first != kb)
        {
            Check(false, "a contact's fixtures have proxies", 0);
            continue;
        }
        overlapping += bp.TestOverlap(a->second, b->second) ? 1 : 0;
    }
    std::printf("%s inline proxies %d contacts whose fat AABBs overlap %d\n", scene, expected, overlapping);
}

struct QueryHits : b2QueryCallback
{
    std::vector<uint64_t> ids;
    bool ReportFixture(b2Fixture* fixture) override
    {
        ids.push_back(Index(fixture));
        return true;
    }
};

struct RayHits : b2RayCastCallback
{
    bool closest = false;
    std::vector<uint64_t> ids;
    float fraction = 1.0f;
    uint64_t closestId = ~uint64_t(0);
    float ReportFixture(b2Fixture* fixture, const b2Vec2&, const b2Vec2&, float f) override
    {
        ids.push_back(Index(fixture));
        if (f < fraction)
        {
            fraction = f;
            closestId = Index(fixture);
        }
        return closest ? f : 1.0f;
    }
};

b2Body* AddBody(b2World& world, b2BodyType type, float x, float y, uint64_t& next)
{
    b2BodyDef def;
    def.type = type;
    def.position.Set(x, y);
    b2Body* body = world.CreateBody(&def);
    (void)next;
    return body;
}

void AddFixture(b2Body* body, const b2Shape& shape, bool sensor, uint64_t& next)
{
    b2FixtureDef fd;
    fd.shape = &shape;
    fd.density = 1.0f;
    fd.isSensor = sensor;
    fd.userData.pointer = uintptr_t(next++);
    body->CreateFixture(&fd);
}

uint32_t g_rng = 12345u;
float Uniform(float lo, float hi)
{
    g_rng = g_rng * 1664525u + 1013904223u;
    return lo + (hi - lo) * float(g_rng >> 8) * (1.0f / 16777216.0f);
}

// A box whose lower corner is uniform in [lo, hi)^2 and whose sides are uniform in [minSide, maxSide).
b2AABB RandomBox(float lo, float hi, float minSide, float maxSide)
{
    b2AABB box;
    box.lowerBound.Set(Uniform(lo, hi), Uniform(lo, hi));
    box.upperBound = box.lowerBound + b2Vec2(Uniform(minSide, maxSide), Uniform(minSide, maxSide));
    return box;
}

void SensorScene()
{
    b2World world(b2Vec2(0.0f, 0.0f));
    uint64_t next = 0;
    // Sensors on dynamic bodies with no gravity and no damping: each moves on a straight line whatever the
    // contacts, so positions, fat AABBs and contacts must be the same on any correct broadphase at every step.
    for (int i = 0; i < 600; ++i)
    {
        b2Body* body = AddBody(world, b2_dynamicBody, Uniform(-50.0f, 50.0f), Uniform(-50.0f, 50.0f), next);
        body->SetLinearVelocity(b2Vec2(Uniform(-4.0f, 4.0f), Uniform(-4.0f, 4.0f)));
        if (i % 3 == 0)
        {
            b2CircleShape circle;
            circle.m_radius = Uniform(0.2f, 1.5f);
            AddFixture(body, circle, true, next);
        }
        else
        {
            b2PolygonShape box;
            box.SetAsBox(Uniform(0.2f, 1.0f), Uniform(0.2f, 1.0f));
            AddFixture(body, box, true, next);
        }
    }
    // A few static sensors, large and small.
    for (int i = 0; i < 10; ++i)
    {
        b2Body* body = AddBody(world, b2_staticBody, Uniform(-40.0f, 40.0f), Uniform(-40.0f, 40.0f), next);
        b2PolygonShape box;
        box.SetAsBox(Uniform(1.0f, 12.0f), Uniform(0.5f, 3.0f));
        AddFixture(body, box, true, next);
    }
    for (int step = 1; step <= 240; ++step)
    {
        world.Step(1.0f / 60.0f, 8, 3);
        if (step % 10 == 0 || step <= 5)
        {
            PrintContacts("sensors", step, world);
        }
        if (step % 60 == 0)
        {
            CheckInline("sensors", world);
            Hash q;
            for (int i = 0; i < 50; ++i)
            {
                QueryHits hits;
                world.QueryAABB(&hits, RandomBox(-60.0f, 50.0f, 0.5f, 15.0f));
                q.AddSet(hits.ids);
            }
            for (int i = 0; i < 50; ++i)
            {
                RayHits all;
                RayHits closest;
                closest.closest = true;
                const b2Vec2 p1(Uniform(-70.0f, 70.0f), Uniform(-70.0f, 70.0f));
                const b2Vec2 p2(Uniform(-70.0f, 70.0f), Uniform(-70.0f, 70.0f));
                world.RayCast(&all, p1, p2);
                world.RayCast(&closest, p1, p2);
                q.AddSorted(all.ids);
                q.Add(closest.closestId);
            }
            std::printf("sensors queries step %d hash %016" PRIx64 "\n", step, q.value);
        }
    }
    // b2World's tree statistics (the library's, through b2BroadPhase's inline ones): stock's tree's, or 0.
    std::printf("templates sensors world tree height %d balance %d quality %a\n", world.GetTreeHeight(),
                world.GetTreeBalance(), double(world.GetTreeQuality()));
}

void PileScene()
{
    b2World world(b2Vec2(0.0f, -10.0f));
    uint64_t next = 0;
    b2Body* ground = AddBody(world, b2_staticBody, 0.0f, 0.0f, next);
    b2EdgeShape edge;
    edge.SetTwoSided(b2Vec2(-40.0f, 0.0f), b2Vec2(40.0f, 0.0f));
    AddFixture(ground, edge, false, next);
    for (int i = 0; i < 400; ++i)
    {
        b2Body* body = AddBody(world, b2_dynamicBody, -20.0f + 1.05f * float(i % 40),
                               0.6f + 1.05f * float(i / 40), next);
        b2PolygonShape box;
        box.SetAsBox(0.5f, 0.5f);
        AddFixture(body, box, false, next);
    }
    for (int step = 1; step <= 300; ++step)
    {
        world.Step(1.0f / 60.0f, 8, 3);
        if (step % 100 == 0)
        {
            CheckInline("pile", world);
        }
    }
    // The world is shifted (b2World::ShiftOrigin, in the library) and the inline reads still hold.
    world.ShiftOrigin(b2Vec2(10.0f, -5.0f));
    world.Step(1.0f / 60.0f, 8, 3);
    CheckInline("pile", world, false);
}

// Stock's inline readers (GetFatAABB, GetUserData, TestOverlap) right after each kind of call that changes a proxy,
// before anything (a Step, a query) would let a lazy broadphase catch up: "edges <when> ..." lines, one per proxy,
// keyed by fixture index and child (proxy ids differ between the libraries: stock's tree numbers its inner nodes
// among the proxies), with the fat AABB's exact bits and which other proxies' fat AABBs it overlaps.
void PrintReaders(const char* when, b2World& world)
{
    const b2BroadPhase& bp = world.GetContactManager().m_broadPhase;
    std::vector<std::pair<std::pair<uint64_t, int32>, int32>> ids; // ((fixture index, child), proxy id)
    // Stops at the last proxy: stock's GetUserData does not check the id against the node array's size.
    for (int32 id = 0; int32(ids.size()) < bp.GetProxyCount() && id < 4 * bp.GetProxyCount() + 16; ++id)
    {
        const b2FixtureProxy* proxy = static_cast<const b2FixtureProxy*>(bp.GetUserData(id));
        // A destroyed proxy's record may keep its user data on stock (a freed node), with proxyId reset.
        if (proxy != nullptr && proxy->proxyId == id)
        {
            ids.push_back(std::make_pair(std::make_pair(Index(proxy->fixture), proxy->childIndex), id));
        }
    }
    std::sort(ids.begin(), ids.end());
    Check(int32(ids.size()) == bp.GetProxyCount(), "every proxy is found through GetUserData",
          long(ids.size()));
    for (size_t i = 0; i < ids.size(); ++i)
    {
        const b2AABB fat = bp.GetFatAABB(ids[i].second);
        std::printf("edges %s f%d.%d [%a %a %a %a] overlaps", when, int(ids[i].first.first),
                    int(ids[i].first.second), double(fat.lowerBound.x), double(fat.lowerBound.y),
                    double(fat.upperBound.x), double(fat.upperBound.y));
        for (size_t j = 0; j < ids.size(); ++j)
        {
            if (j != i && bp.TestOverlap(ids[i].second, ids[j].second))
            {
                std::printf(" f%d.%d", int(ids[j].first.first), int(ids[j].first.second));
            }
        }
        std::printf("\n");
    }
}

void EdgeScene()
{
    b2World world(b2Vec2(0.0f, 0.0f));
    uint64_t next = 0;
    b2PolygonShape box;
    box.SetAsBox(0.5f, 0.5f);
    b2CircleShape circle;
    circle.m_radius = 0.75f;
    b2Body* a = AddBody(world, b2_dynamicBody, 0.0f, 0.0f, next);
    AddFixture(a, box, false, next);
    b2Body* b = AddBody(world, b2_dynamicBody, 3.0f, 0.0f, next);
    AddFixture(b, circle, true, next);
    b2Body* ground = AddBody(world, b2_staticBody, 0.0f, -2.0f, next);
    b2Vec2 points[4] = {b2Vec2(-10.0f, 0.0f), b2Vec2(0.0f, 0.5f), b2Vec2(10.0f, 0.0f), b2Vec2(30.0f, 1.0f)};
    b2ChainShape chain;
    chain.CreateChain(points, 4, points[0], points[3]);
    AddFixture(ground, chain, false, next);
    PrintReaders("created", world);
    world.Step(1.0f / 60.0f, 8, 3);
    PrintReaders("stepped", world);
    // CreateProxy between steps.
    b2Body* c = AddBody(world, b2_dynamicBody, 27.0f, 0.5f, next);
    AddFixture(c, box, false, next);
    PrintReaders("created-between-steps", world);
    // MoveProxy through b2Body::SetTransform: far (a new fat box), then onto c (TestOverlap turns true).
    a->SetTransform(b2Vec2(27.0f, 0.0f), 0.0f);
    PrintReaders("teleported", world);
    // A small move inside the fat box (the stored box stays), and a move that shrinks nothing.
    b->SetTransform(b2Vec2(3.05f, 0.0f), 0.0f);
    PrintReaders("nudged", world);
    // Moved twice before anything reads the broadphase through the library.
    b->SetTransform(b2Vec2(-8.0f, 4.0f), 0.5f);
    b->SetTransform(b2Vec2(-8.5f, 4.0f), 0.7f);
    PrintReaders("moved-twice", world);
    // TouchProxy (b2Fixture::Refilter) after a move.
    a->SetTransform(b2Vec2(20.0f, 1.0f), 1.0f);
    a->GetFixtureList()->Refilter();
    PrintReaders("touched", world);
    // Destroyed and created again (b2Body::SetEnabled), then the origin shifts with a move still pending.
    b->SetEnabled(false);
    PrintReaders("disabled", world);
    b->SetEnabled(true);
    c->SetTransform(b2Vec2(-3.0f, -1.0f), 0.0f);
    world.ShiftOrigin(b2Vec2(5.0f, -2.0f));
    PrintReaders("shifted", world);
    world.Step(1.0f / 60.0f, 8, 3);
    PrintReaders("stepped-again", world);
}

#ifndef SWAP_PROBE_NO_TEMPLATES
// Stock's inline templates (UpdatePairs, Query, RayCast) and tree statistics of a b2BroadPhase the program drives
// itself: "templates ..." lines. On quadphase's library they give stock's answers with QUADPHASE_STOCK_TREE=1 only
// (docs/design.md, "Binary compatibility"). Not in the reverse build: quadphase's header makes these templates call
// the library's QueryWith, RayCastWith and UpdatePairsWith, which stock's library lacks.
struct PairCollector
{
    std::vector<std::pair<uintptr_t, uintptr_t>> pairs;
    void AddPair(void* a, void* b)
    {
        uintptr_t x = reinterpret_cast<uintptr_t>(a);
        uintptr_t y = reinterpret_cast<uintptr_t>(b);
        pairs.push_back(std::make_pair(std::min(x, y), std::max(x, y)));
    }
};

struct HitCollector
{
    const b2BroadPhase* bp;
    std::vector<uintptr_t> hits;
    bool QueryCallback(int32 id)
    {
        hits.push_back(reinterpret_cast<uintptr_t>(bp->GetUserData(id)));
        return true;
    }
    float RayCastCallback(const b2RayCastInput& input, int32 id)
    {
        hits.push_back(reinterpret_cast<uintptr_t>(bp->GetUserData(id)));
        return input.maxFraction;
    }
};

void PrintPairs(const char* when, b2BroadPhase& bp)
{
    PairCollector collector;
    bp.UpdatePairs(&collector);
    std::sort(collector.pairs.begin(), collector.pairs.end());
    collector.pairs.erase(std::unique(collector.pairs.begin(), collector.pairs.end()), collector.pairs.end());
    Hash h;
    for (size_t i = 0; i < collector.pairs.size(); ++i)
    {
        h.Add(collector.pairs[i].first);
        h.Add(collector.pairs[i].second);
    }
    std::printf("templates %s UpdatePairs %zu pairs hash %016" PRIx64 "\n", when, collector.pairs.size(),
                h.value);
}

void TemplateScene()
{
    b2BroadPhase bp;
    std::vector<int32> ids;
    for (int i = 0; i < 300; ++i)
    {
        const b2AABB box = RandomBox(-40.0f, 40.0f, 0.2f, 3.0f);
        ids.push_back(bp.CreateProxy(box, reinterpret_cast<void*>(uintptr_t(i + 1))));
    }
    PrintPairs("created", bp);
    for (int round = 0; round < 5; ++round)
    {
        for (int k = 0; k < 60; ++k)
        {
            const int32 id = ids[size_t((round * 61 + k * 7) % 300)];
            if (id == b2BroadPhase::e_nullProxy)
            {
                continue;
            }
            const b2AABB& fat = bp.GetFatAABB(id);
            const b2Vec2 d(Uniform(-1.5f, 1.5f), Uniform(-1.5f, 1.5f));
            b2AABB box;
            box.lowerBound = fat.lowerBound + b2Vec2(0.1f, 0.1f) + d;
            box.upperBound = fat.upperBound - b2Vec2(0.1f, 0.1f) + d;
            bp.MoveProxy(id, box, d);
        }
        bp.TouchProxy(ids[size_t(round * 13 + 1)]);
        const size_t destroyed = size_t(round * 17 + 5);
        if (ids[destroyed] != b2BroadPhase::e_nullProxy)
        {
            bp.DestroyProxy(ids[destroyed]);
            ids[destroyed] = b2BroadPhase::e_nullProxy;
        }
        PrintPairs("moved", bp);
    }
    Hash q;
    for (int i = 0; i < 30; ++i)
    {
        HitCollector hits;
        hits.bp = &bp;
        bp.Query(&hits, RandomBox(-45.0f, 40.0f, 0.5f, 12.0f));
        q.AddSet(hits.hits);
    }
    for (int i = 0; i < 30; ++i)
    {
        HitCollector hits;
        hits.bp = &bp;
        b2RayCastInput input;
        input.p1.Set(Uniform(-50.0f, 50.0f), Uniform(-50.0f, 50.0f));
        input.p2.Set(Uniform(-50.0f, 50.0f), Uniform(-50.0f, 50.0f));
        input.maxFraction = 1.0f;
        bp.RayCast(&hits, input);
        q.AddSet(hits.hits);
    }
    std::printf("templates Query and RayCast hash %016" PRIx64 "\n", q.value);
    std::printf("templates tree height %d balance %d quality %a\n", bp.GetTreeHeight(), bp.GetTreeBalance(),
                double(bp.GetTreeQuality()));
}
#endif

void PrintLibrary()
{
    Dl_info info;
    const char* path = "?";
    if (dladdr(reinterpret_cast<void*>(&b2Alloc_Default), &info) != 0 && info.dli_fname != nullptr)
    {
        path = info.dli_fname;
    }
    // quadphase::SetValidation(b2World&, bool): only quadphase's library defines it.
    const bool quadphase = dlsym(RTLD_DEFAULT, "_ZN9quadphase13SetValidationER7b2Worldb") != nullptr;
    std::printf("library %s %s\n", path, quadphase ? "quadphase" : "stock");
}

} // namespace

int main()
{
    PrintLibrary();
    EdgeScene();
#ifndef SWAP_PROBE_NO_TEMPLATES
    TemplateScene();
#endif
    SensorScene();
    PileScene();
    std::printf("inline failures %d\n", g_failures);
    return g_failures == 0 ? 0 : 1;
}
