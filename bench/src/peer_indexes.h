// SPDX-License-Identifier: MIT
// The foreign spatial indexes qp-replay's peers run over (replay_peers.cpp), each behind one small interface:
//   Insert(id, fat), Update(id, fat), Remove(id)  the box the index keeps for `id` (Box2D's fat box)
//   Query(fat, fn(int32_t id))                     every id whose indexed box may overlap `fat` (a superset)
//   AllPairs(fn(int32_t a, int32_t b))             the index's own per-step loop (native mode): every pair
//                                                  whose indexed boxes may overlap, each once (a superset)
// Ids are the engine's (0..n-1); the engine filters what an index returns with the exact fat-box test.
#pragma once

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "proxy_pool.h"
#include "quadphase/box.h"
#include "quadtree_broad_phase.h"

#if QP_HAVE_CHIPMUNK
#include <chipmunk/chipmunk.h>
#endif
#if QP_HAVE_BULLET
#include <BulletCollision/BroadphaseCollision/btAxisSweep3.h>
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/BroadphaseCollision/btOverlappingPairCache.h>
#endif

namespace qpbench
{

using quadphase::Box;

/// quadphase's own core as a plain index (exact; for the oracle's untimed preparation only).
class QuadIndex
{
public:
    explicit QuadIndex(const quadphase::ProxyPool*) {}
    void Insert(int32_t id, const Box& fat)
    {
        if (size_t(id) >= m_ids.size())
        {
            m_ids.resize(size_t(id) + 1, -1);
        }
        m_ids[size_t(id)] = m_bp.CreateProxy(fat, reinterpret_cast<void*>(intptr_t(id)));
    }
    void Update(int32_t id, const Box& fat) { m_bp.MoveProxy(m_ids[size_t(id)], fat, quadphase::Vec2{0, 0}); }
    void Remove(int32_t id) { m_bp.DestroyProxy(m_ids[size_t(id)]); }
    template <typename Fn>
    void Query(const Box& b, Fn&& fn)
    {
        std::pair context{&fn, &m_bp};
        m_bp.Query(
            b,
            [](void* c, quadphase::ProxyId p) {
                const auto& [f, bp] = *static_cast<decltype(context)*>(c);
                (*f)(int32_t(intptr_t(bp->GetUserData(p))));
                return true;
            },
            &context);
    }

private:
    quadphase::QuadtreeBroadPhase m_bp{quadphase::FatPolicy{}, quadphase::Config{}};
    std::vector<quadphase::ProxyId> m_ids;
};

#if QP_HAVE_CHIPMUNK
/// Chipmunk2D 7: cpSpaceHash (cell side `cell`, `cells` buckets) or cpBBTree (no velocity function).
/// Chipmunk's bounding-box callback carries no context: the current engine's boxes are a global (one engine
/// at a time).
inline const quadphase::ProxyPool* g_cpPool = nullptr;

class ChipmunkIndex
{
public:
    ChipmunkIndex(const quadphase::ProxyPool* pool, bool hash, double cell, int cells)
        : m_index(hash ? cpSpaceHashNew(cell, cells, BB, nullptr) : cpBBTreeNew(BB, nullptr))
    {
        g_cpPool = pool;
    }
    ~ChipmunkIndex() { cpSpatialIndexFree(m_index); }
    ChipmunkIndex(const ChipmunkIndex&) = delete;
    ChipmunkIndex& operator=(const ChipmunkIndex&) = delete;

    void Insert(int32_t id, const Box&) { cpSpatialIndexInsert(m_index, Obj(id), cpHashValue(id)); }
    void Update(int32_t id, const Box&) { cpSpatialIndexReindexObject(m_index, Obj(id), cpHashValue(id)); }
    void Remove(int32_t id) { cpSpatialIndexRemove(m_index, Obj(id), cpHashValue(id)); }
    template <typename Fn>
    void Query(const Box& b, Fn&& fn)
    {
        cpSpatialIndexQuery(m_index, nullptr, cpBBNew(b.minX, b.minY, b.maxX, b.maxY), &One<Fn>, &fn);
    }
    /// cpSpatialIndexReindexQuery: what cpSpace's step does (the hash re-hashes every object; the tree
    /// updates the leaves whose box left theirs and reports its cached pairs).
    template <typename Fn>
    void AllPairs(Fn&& fn)
    {
        cpSpatialIndexReindexQuery(m_index, &Two<Fn>, &fn);
    }

private:
    static cpBB BB(void* obj)
    {
        const Box& b = g_cpPool->Fat(Id(obj));
        return cpBBNew(b.minX, b.minY, b.maxX, b.maxY);
    }
    template <typename Fn>
    static cpCollisionID One(void*, void* obj, cpCollisionID id, void* fn)
    {
        (*static_cast<Fn*>(fn))(Id(obj));
        return id;
    }
    template <typename Fn>
    static cpCollisionID Two(void* a, void* b, cpCollisionID id, void* fn)
    {
        (*static_cast<Fn*>(fn))(Id(a), Id(b));
        return id;
    }
    static void* Obj(int32_t id) { return reinterpret_cast<void*>(uintptr_t(id) + 1); }
    static int32_t Id(void* obj) { return int32_t(uintptr_t(obj) - 1); }
    cpSpatialIndex* m_index;
};
#endif

#if QP_HAVE_BULLET
/// Bullet 3: btDbvtBroadphase, or bt32BitAxisSweep3 over `world` (sap). Native mode uses the broadphase's own
/// pair cache (calculateOverlappingPairs, then the cache's pairs); Box2D's protocol queries with aabbTest,
/// with collisions deferred so that setAabb does no pair-cache work.
class BulletIndex
{
public:
    BulletIndex(const quadphase::ProxyPool*, bool native, bool sap, const Box& world, int maxProxies)
    {
        if (sap)
        {
            m_bp.reset(new bt32BitAxisSweep3(btVector3(world.minX, world.minY, -1),
                                             btVector3(world.maxX, world.maxY, 1), unsigned(maxProxies + 2),
                                             nullptr, true));
        }
        else
        {
            btDbvtBroadphase* dbvt = new btDbvtBroadphase();
            dbvt->m_deferedcollide = !native;
            m_bp.reset(dbvt);
        }
    }
    ~BulletIndex()
    {
        for (btBroadphaseProxy* p : m_proxies)
        {
            if (p != nullptr)
            {
                m_bp->destroyProxy(p, nullptr);
            }
        }
    }
    BulletIndex(const BulletIndex&) = delete;
    BulletIndex& operator=(const BulletIndex&) = delete;

    void Insert(int32_t id, const Box& b)
    {
        if (size_t(id) >= m_proxies.size())
        {
            m_proxies.resize(size_t(id) + 1, nullptr);
        }
        m_proxies[size_t(id)] =
            m_bp->createProxy(Min(b), Max(b), 0, reinterpret_cast<void*>(intptr_t(id)), 1, -1, nullptr);
    }
    void Update(int32_t id, const Box& b) { m_bp->setAabb(m_proxies[size_t(id)], Min(b), Max(b), nullptr); }
    void Remove(int32_t id)
    {
        m_bp->destroyProxy(m_proxies[size_t(id)], nullptr);
        m_proxies[size_t(id)] = nullptr;
    }
    template <typename Fn>
    void Query(const Box& b, Fn&& fn)
    {
        struct Callback : btBroadphaseAabbCallback
        {
            explicit Callback(Fn& f) : fn(f) {}
            bool process(const btBroadphaseProxy* proxy) override
            {
                fn(int32_t(intptr_t(proxy->m_clientObject)));
                return true;
            }
            Fn& fn;
        } callback(fn);
        m_bp->aabbTest(Min(b), Max(b), callback);
    }
    template <typename Fn>
    void AllPairs(Fn&& fn)
    {
        m_bp->calculateOverlappingPairs(nullptr);
        const btBroadphasePairArray& pairs = m_bp->getOverlappingPairCache()->getOverlappingPairArray();
        for (int i = 0; i < pairs.size(); ++i)
        {
            fn(int32_t(intptr_t(pairs[i].m_pProxy0->m_clientObject)),
               int32_t(intptr_t(pairs[i].m_pProxy1->m_clientObject)));
        }
    }

private:
    static btVector3 Min(const Box& b) { return btVector3(b.minX, b.minY, 0.0f); }
    static btVector3 Max(const Box& b) { return btVector3(b.maxX, b.maxY, 0.0f); }
    std::unique_ptr<btBroadphaseInterface> m_bp;
    std::vector<btBroadphaseProxy*> m_proxies;
};
#endif

/// The oracle's "index": no search at all. It hands out, query by query, the pairs an exact index gave for
/// the same query in an untimed preparation run (replay_peers.cpp's PeerEngine records them).
class OracleIndex
{
public:
    OracleIndex(const quadphase::ProxyPool*, std::vector<std::pair<int32_t, int32_t>> pairs,
                std::vector<int32_t> perQuery)
        : m_pairs(std::move(pairs)), m_perQuery(std::move(perQuery))
    {
    }
    void Insert(int32_t, const Box&) {}
    void Update(int32_t, const Box&) {}
    void Remove(int32_t) {}
    /// Appends the next query's precomputed pairs.
    void Append(std::vector<std::pair<int32_t, int32_t>>& out)
    {
        const int32_t n = m_perQuery[m_query++];
        out.insert(out.end(), m_pairs.begin() + m_next, m_pairs.begin() + m_next + n);
        m_next += size_t(n);
    }

private:
    std::vector<std::pair<int32_t, int32_t>> m_pairs;
    std::vector<int32_t> m_perQuery;
    size_t m_query = 0, m_next = 0;
};

} // namespace qpbench
