// SPDX-License-Identifier: MIT
// libFuzzer target at the Box2D level: random call sequences on quadphase's b2BroadPhase (the adapter every
// game calls), each answer checked against Box2D 2.4.1's own b2BroadPhase compiled into the same process
// (stock/stock_broad_phase.h). Only b2BroadPhase's stock public API and the free functions of
// <quadphase/box2d.h> are used, so the target does not depend on how the adapter is built.
//
// The input is a byte string read as a program (tests/fuzz/fuzz_input.h; box2d_fuzz_format.h names the
// opcodes, which tests/fuzz/trace_to_input.cpp writes from recorded scene traces). Byte 0 picks validation
// mode and the quadtree's Config (automatic or fixed depth, 1, 2 or automatic threads, parallel paths from 2
// proxies or the default). Each operation is an opcode byte and its operands:
//   create; move (a body's step: its box shifted by the displacement, or a new box, or a box given bit for
//   bit); destroy; touch; UpdatePairs; a step (many moves, then UpdatePairs); Query; RayCast; ShiftOrigin; a
//   full check; and meta operations: validation on/off, Configure, SetTrace on/off, the tree statistics.
// Query and RayCast come plain, stopped at the first hit, as closest-hit casts (the callback clips the ray at
// the proxy's tight box, as b2World::RayCast's closest-hit callbacks do), and re-entrant: the callback then
// creates, destroys, moves and touches proxies, runs nested queries, and may stop the call.
//
// What must hold (else the target prints the divergence and aborts, which libFuzzer reports as a crash):
// - bit-identical fat AABBs (GetFatAABB), the same GetProxyCount, GetUserData and TestOverlap;
// - per UpdatePairs, the same pair set (stock may repeat a pair, quadphase must not);
// - plain Query and all-hits RayCast: the same proxies; first-hit: one call exactly when stock has a hit;
//   closest-hit: the same closest fraction, and the proxy reported hit at that fraction;
// - re-entrant calls, what both contracts promise (QuadtreeBroadPhase::Query): a proxy that existed before
// the
//   call and was neither moved nor destroyed during it is reported exactly once (unless the callback stopped
//   or clipped the call); a proxy destroyed during the call is never reported after; a proxy created or moved
//   during the call is reported only if its fat box overlaps the query (crosses the segment) at that moment;
//   no proxy twice; an untouched proxy stock does not find is never reported. Afterwards the quadtree's
//   Validate() holds;
// - no error report at all (every input is valid: boxes are finite and ordered, ids are live), validation
// mode
//   included (a mismatch is reported through the same hook);
// - SetTrace records exactly the calls made, bit for bit.
// Built as a fuzzer by scripts/fuzz.sh --target box2d; replayed over tests/fuzz/corpus/box2d by
// fuzz_replay_main.cpp in every normal test run.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "box2d/b2_broad_phase.h"
#include "box2d_fuzz_format.h"
#include "box2d_internal.h"
#include "fuzz_input.h"
#include "fuzz_stats.h"
#include "quadphase/box2d.h"
#include "quadphase/error.h"
#include "ray.h"
#include "stock/stock_broad_phase.h"
#include "strict_segment.h"
#include "trace.h"

namespace
{

using quadphase::fuzz::Reader;
using quadphase::fuzz::StockBroadPhase;
namespace op = quadphase::fuzz::box2d_op;

constexpr int kMaxOps = 2000;
constexpr int kMaxLive = 600;
constexpr int kMaxActionsPerCall = 24; // re-entrant actions in one Query or RayCast

int g_op = 0;

// QP_FUZZ_TRACE=1: print every call as it is made (to read a crashing input).
const bool g_trace = [] {
    const char* v = std::getenv("QP_FUZZ_TRACE");
    return v != nullptr && std::strcmp(v, "1") == 0;
}();

#define TRACE(...)                                                                                           \
    do                                                                                                       \
    {                                                                                                        \
        if (g_trace)                                                                                         \
        {                                                                                                    \
            std::fprintf(stderr, "[%d] ", g_op);                                                             \
            std::fprintf(stderr, __VA_ARGS__);                                                               \
            std::fputc('\n', stderr);                                                                        \
        }                                                                                                    \
    } while (false)

[[noreturn]] void Diverge(const char* what, long a, long b)
{
    std::fprintf(stderr, "box2d_fuzz: DIVERGENCE at operation %d: %s (quadphase %ld, stock %ld)\n", g_op,
                 what, a, b);
    std::abort();
}

// Every input is valid, so any report (validation mismatches included) is a divergence.
void OnError(quadphase::ErrorCode, const char* message, void*)
{
    std::fprintf(stderr, "box2d_fuzz: error report: %s\n", message);
    Diverge("an error was reported for valid input", 1, 0);
}

/// Prints the ids in one sorted list and not the other (before a divergence on two sets).
void PrintDifference(const char* what, const std::vector<int32_t>& a, const std::vector<int32_t>& b)
{
    std::vector<int32_t> onlyA, onlyB;
    std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(onlyA));
    std::set_difference(b.begin(), b.end(), a.begin(), a.end(), std::back_inserter(onlyB));
    std::fprintf(stderr, "box2d_fuzz: %s: only quadphase:", what);
    for (int32_t id : onlyA)
    {
        std::fprintf(stderr, " %d", id);
    }
    std::fprintf(stderr, "; only the reference:");
    for (int32_t id : onlyB)
    {
        std::fprintf(stderr, " %d", id);
    }
    std::fprintf(stderr, "\n");
}

bool SameBits(const b2AABB& a, const b2AABB& b)
{
    return std::memcmp(&a, &b, sizeof(b2AABB)) == 0;
}

b2AABB ToAABB(const quadphase::Box& b)
{
    b2AABB a;
    a.lowerBound.Set(b.minX, b.minY);
    a.upperBound.Set(b.maxX, b.maxY);
    return a;
}

quadphase::Box ToBox(const b2AABB& a)
{
    return quadphase::Box{a.lowerBound.x, a.lowerBound.y, a.upperBound.x, a.upperBound.y};
}

// User data: a distinct fake pointer per created proxy (never dereferenced), from its creation serial.
void* UserData(int32_t serial)
{
    return reinterpret_cast<void*>((uintptr_t(serial) + 1) * 16);
}
int32_t SerialOf(void* userData)
{
    return int32_t(reinterpret_cast<uintptr_t>(userData) / 16) - 1;
}

// Where the segment enters `tight` (b2AABB::RayCast, so the arithmetic of a game's fixture test), or -1.
float EntryFraction(const b2AABB& tight, const b2RayCastInput& input)
{
    b2RayCastOutput out;
    return tight.RayCast(&out, input) ? out.fraction : -1.0f;
}

/// b2DynamicTree::RayCast's test for one node, with Box2D's own arithmetic (b2_dynamic_tree.h): the segment's
/// bounding box must overlap the node's AABB, and the separating axis along the segment's normal must not
/// separate them.
class LeafTest
{
public:
    explicit LeafTest(const b2RayCastInput& input) : m_p1(input.p1)
    {
        b2Vec2 r = input.p2 - input.p1;
        r.Normalize();
        m_v = b2Cross(1.0f, r);
        m_absV = b2Abs(m_v);
        const b2Vec2 t = m_p1 + input.maxFraction * (input.p2 - m_p1);
        m_segment.lowerBound = b2Min(m_p1, t);
        m_segment.upperBound = b2Max(m_p1, t);
    }

    bool Crosses(const b2AABB& aabb) const
    {
        if (!b2TestOverlap(aabb, m_segment))
        {
            return false;
        }
        const b2Vec2 c = aabb.GetCenter();
        const b2Vec2 h = aabb.GetExtents();
        const float separation = b2Abs(b2Dot(m_v, m_p1 - c)) - b2Dot(m_absV, h);
        return !(separation > 0.0f);
    }

private:
    b2Vec2 m_p1;
    b2Vec2 m_v;
    b2Vec2 m_absV;
    b2AABB m_segment;
};

struct Proxy
{
    int32 qp = -1;    // quadphase's id
    int32 stock = -1; // stock's id
    int32_t serial = -1;
    b2AABB tight{};
};

/// Reused across inputs: no allocation per operation once grown.
struct Scratch
{
    std::vector<std::pair<void*, void*>> quadphasePairs, stockPairs;
    std::vector<std::pair<int32_t, int32_t>> a, b;
    std::vector<int32_t> ids, other, third, fourth;
};

class Run;

/// quadphase's b2BroadPhase::UpdatePairs callback.
struct PairRecorder
{
    std::vector<std::pair<void*, void*>>* out;
    void AddPair(void* userDataA, void* userDataB) { out->emplace_back(userDataA, userDataB); }
};

class Run
{
public:
    Run(uint8_t configByte, Scratch& scratch) : m_s(scratch)
    {
        quadphase::Config c;
        const int depths[] = {-1, -1, -1, -1, 1, 3, 5, 6};
        c.depth = depths[configByte >> 5];
        const int threads[] = {1, 1, 0, 2};
        c.threads = threads[(configByte >> 2) & 3];
        c.parallelThreshold = ((configByte >> 4) & 1) != 0 ? 2 : 128;
        quadphase::GetQuadtree(m_bp).Configure(c);
        if ((configByte & 3) == 3)
        {
            quadphase::SetValidation(m_bp, true);
        }
    }

    ~Run()
    {
        if (m_tracing)
        {
            quadphase::SetTrace(m_bp, nullptr);
        }
    }

    void Execute(Reader& in)
    {
        m_in = &in;
        for (g_op = 0; g_op < kMaxOps && !in.Done(); ++g_op)
        {
            switch (op::kTable[in.Byte() % 16])
            {
            case op::kCreate:
                Create(ReadAABB());
                break;
            case op::kMove:
                Move();
                break;
            case op::kDestroy:
                Destroy(ReadHandle());
                break;
            case op::kTouch:
                Touch(ReadHandle());
                break;
            case op::kUpdatePairs:
                UpdatePairs();
                break;
            case op::kStep:
                Step();
                break;
            case op::kQuery:
                Query();
                break;
            case op::kRayCast:
                RayCast();
                break;
            case op::kShiftOrigin:
                ShiftOrigin();
                break;
            case op::kCheck:
                CheckAll();
                break;
            case op::kMeta:
                Meta();
                break;
            }
        }
        UpdatePairs();
        CheckAll();
        if (m_tracing)
        {
            StopTrace();
        }
        quadphase::fuzz::g_stats.operations += g_op;
    }

private:
    // ---- reading operands ----

    b2AABB ReadAABB()
    {
        bool sane = true;
        return ToAABB(quadphase::fuzz::ReadBox(*m_in, false, sane));
    }

    b2Vec2 ReadVector(float scaleSmall, float scaleLarge)
    {
        const uint8_t mode = m_in->Byte();
        if (mode == quadphase::fuzz::kRawBox)
        {
            float x = m_in->Raw();
            float y = m_in->Raw();
            return b2Vec2(std::isfinite(x) ? x : 0.0f, std::isfinite(y) ? y : 0.0f);
        }
        const float scale = (mode & 1) != 0 ? scaleLarge : scaleSmall;
        const float x = m_in->Signed() * scale;
        const float y = m_in->Signed() * scale;
        return b2Vec2(x, y);
    }

    /// A live proxy (its quadphase id), or -1 when there is none. Ids with the top bit set name a quadphase
    /// id directly (what the trace converter writes), falling back to an index when that id is not live.
    int32 ReadHandle()
    {
        const uint16_t v = m_in->U16();
        if (m_live.empty())
        {
            return -1;
        }
        if ((v & op::kDirectId) != 0)
        {
            const int32 id = int32(v & 0x7fff);
            if (IsLive(id))
            {
                return id;
            }
        }
        return m_live[size_t(v & 0x7fff) % m_live.size()];
    }

    bool IsLive(int32 qp) const { return qp >= 0 && size_t(qp) < m_slot.size() && m_slot[size_t(qp)] >= 0; }

    // ---- the calls, mirrored on both broadphases ----

    /// Returns the new proxy's quadphase id, or -1 at the limit.
    int32 Create(const b2AABB& box)
    {
        if (int(m_live.size()) >= kMaxLive)
        {
            return -1;
        }
        const int32_t serial = m_serials++;
        const int32 qp = m_bp.CreateProxy(box, UserData(serial));
        const int32 stock = m_stock.CreateProxy(box, UserData(serial));
        TRACE("CreateProxy (%.9g, %.9g)-(%.9g, %.9g) -> %d (stock %d)", box.lowerBound.x, box.lowerBound.y,
              box.upperBound.x, box.upperBound.y, qp, stock);
        Expect({quadphase::TraceOp::Create, qp, ToBox(box), {}});
        if (qp < 0 || IsLive(qp))
        {
            Diverge("CreateProxy: id not new", qp, stock);
        }
        if (size_t(qp) >= m_slot.size())
        {
            m_slot.resize(size_t(qp) + 1, -1);
            m_proxy.resize(size_t(qp) + 1);
            m_flags.resize(size_t(qp) + 1, 0);
        }
        if (size_t(stock) >= m_qpOfStock.size())
        {
            m_qpOfStock.resize(size_t(stock) + 1, -1);
        }
        if (size_t(serial) >= m_qpOfSerial.size())
        {
            m_qpOfSerial.resize(size_t(serial) + 1, -1);
        }
        m_slot[size_t(qp)] = int32(m_live.size());
        m_live.push_back(qp);
        m_proxy[size_t(qp)] = Proxy{qp, stock, serial, box};
        m_qpOfStock[size_t(stock)] = qp;
        m_qpOfSerial[size_t(serial)] = qp;
        CompareProxy(qp, "CreateProxy");
        if (m_bp.GetProxyCount() != m_stock.GetProxyCount())
        {
            Diverge("CreateProxy: GetProxyCount", m_bp.GetProxyCount(), m_stock.GetProxyCount());
        }
        return qp;
    }

    void Move()
    {
        const int32 qp = ReadHandle();
        const uint8_t flags = m_in->Byte();
        const b2Vec2 d = ReadVector(0.05f, 4.0f);
        if (qp < 0)
        {
            return;
        }
        b2AABB box;
        if ((flags & 1) != 0)
        {
            // a body's step: its shape moved by the displacement
            const b2AABB& t = m_proxy[size_t(qp)].tight;
            box.lowerBound = t.lowerBound + d;
            box.upperBound = t.upperBound + d;
        }
        else
        {
            box = ReadAABB();
        }
        MoveProxy(qp, box, d);
        if ((flags & 2) != 0)
        {
            CompareProxy(qp, "MoveProxy"); // reads the fat AABB now: applies quadphase's queued moves
        }
    }

    void MoveProxy(int32 qp, const b2AABB& box, const b2Vec2& d)
    {
        if (!quadphase::IsSane(ToBox(box)) || !std::isfinite(d.x) || !std::isfinite(d.y))
        {
            return; // a shift or a velocity that overflowed: not a call a valid world makes
        }
        Proxy& p = m_proxy[size_t(qp)];
        TRACE("MoveProxy %d (%.9g, %.9g)-(%.9g, %.9g) d (%.9g, %.9g)", qp, box.lowerBound.x, box.lowerBound.y,
              box.upperBound.x, box.upperBound.y, d.x, d.y);
        m_bp.MoveProxy(qp, box, d);
        m_stock.MoveProxy(p.stock, box, d);
        Expect({quadphase::TraceOp::Move, qp, ToBox(box), {d.x, d.y}});
        p.tight = box;
    }

    void Destroy(int32 qp)
    {
        if (qp < 0)
        {
            return;
        }
        const Proxy p = m_proxy[size_t(qp)];
        TRACE("DestroyProxy %d", qp);
        m_bp.DestroyProxy(qp);
        m_stock.DestroyProxy(p.stock);
        Expect({quadphase::TraceOp::Destroy, qp, {}, {}});
        const int32 slot = m_slot[size_t(qp)];
        m_live[size_t(slot)] = m_live.back();
        m_slot[size_t(m_live[size_t(slot)])] = slot;
        m_live.pop_back();
        m_slot[size_t(qp)] = -1;
        m_qpOfStock[size_t(p.stock)] = -1;
        m_qpOfSerial[size_t(p.serial)] = -1;
        if (m_bp.GetProxyCount() != m_stock.GetProxyCount() || m_bp.GetProxyCount() != int32(m_live.size()))
        {
            Diverge("DestroyProxy: GetProxyCount", m_bp.GetProxyCount(), m_stock.GetProxyCount());
        }
    }

    void Touch(int32 qp)
    {
        if (qp < 0)
        {
            return;
        }
        TRACE("TouchProxy %d", qp);
        m_bp.TouchProxy(qp);
        m_stock.TouchProxy(m_proxy[size_t(qp)].stock);
        Expect({quadphase::TraceOp::Touch, qp, {}, {}});
    }

    // Pairs as sorted (smaller serial, larger serial).
    void Normalise(const std::vector<std::pair<void*, void*>>& in,
                   std::vector<std::pair<int32_t, int32_t>>& out)
    {
        out.clear();
        for (const auto& pr : in)
        {
            const int32_t a = SerialOf(pr.first);
            const int32_t b = SerialOf(pr.second);
            if (a < 0 || b < 0 || size_t(a) >= m_qpOfSerial.size() || size_t(b) >= m_qpOfSerial.size() ||
                m_qpOfSerial[size_t(a)] < 0 || m_qpOfSerial[size_t(b)] < 0 || a == b)
            {
                Diverge("UpdatePairs: a pair with bad user data", a, b);
            }
            out.emplace_back(std::min(a, b), std::max(a, b));
        }
        std::sort(out.begin(), out.end());
    }

    void UpdatePairs()
    {
        m_s.quadphasePairs.clear();
        m_s.stockPairs.clear();
        PairRecorder recorder{&m_s.quadphasePairs};
        TRACE("UpdatePairs");
        m_bp.UpdatePairs(&recorder);
        m_stock.UpdatePairs(m_s.stockPairs);
        Expect({quadphase::TraceOp::UpdatePairs, -1, {}, {}});
        Normalise(m_s.quadphasePairs, m_s.a);
        Normalise(m_s.stockPairs, m_s.b);
        if (std::adjacent_find(m_s.a.begin(), m_s.a.end()) != m_s.a.end())
        {
            Diverge("UpdatePairs: quadphase reported a pair twice", long(m_s.a.size()), long(m_s.b.size()));
        }
        m_s.b.erase(std::unique(m_s.b.begin(), m_s.b.end()), m_s.b.end()); // stock may repeat a pair
        if (m_s.a != m_s.b)
        {
            Diverge("UpdatePairs: pair sets", long(m_s.a.size()), long(m_s.b.size()));
        }
        if (quadphase::IsValidating(m_bp) && quadphase::GetValidationReport(m_bp).mismatches != 0)
        {
            Diverge("validation mode: mismatches", long(quadphase::GetValidationReport(m_bp).mismatches), 0);
        }
    }

    /// One world step's broadphase work: a share of the proxies move by a common velocity (each slightly
    /// differently), then UpdatePairs.
    void Step()
    {
        const b2Vec2 v = ReadVector(0.05f, 1.0f);
        const uint8_t share = m_in->Byte();
        for (size_t i = 0; i < m_live.size(); ++i)
        {
            const int32 qp = m_live[i];
            const uint32_t h = uint32_t(m_proxy[size_t(qp)].serial) * 2654435761u;
            if ((h >> 24) > share)
            {
                continue;
            }
            const float jitter = float(int((h >> 8) & 0xff) - 128) / 1024.0f;
            const b2Vec2 d(v.x * (1.0f + jitter), v.y * (1.0f - jitter));
            const b2AABB& t = m_proxy[size_t(qp)].tight;
            b2AABB box;
            box.lowerBound = t.lowerBound + d;
            box.upperBound = t.upperBound + d;
            MoveProxy(qp, box, d);
        }
        UpdatePairs();
    }

    void ShiftOrigin()
    {
        const b2Vec2 origin = ReadVector(16.0f, 1.0e4f);
        TRACE("ShiftOrigin (%.9g, %.9g)", origin.x, origin.y);
        m_bp.ShiftOrigin(origin);
        m_stock.ShiftOrigin(origin);
        Expect({quadphase::TraceOp::ShiftOrigin, -1, {}, {origin.x, origin.y}});
        for (int32 qp : m_live)
        {
            b2AABB& t = m_proxy[size_t(qp)].tight;
            t.lowerBound -= origin;
            t.upperBound -= origin;
        }
        CheckAll();
    }

    // ---- checks ----

    void CompareProxy(int32 qp, const char* call)
    {
        const Proxy& p = m_proxy[size_t(qp)];
        if (!SameBits(m_bp.GetFatAABB(qp), m_stock.GetFatAABB(p.stock)))
        {
            std::fprintf(stderr, "box2d_fuzz: %s: fat AABB of proxy %d\n", call, qp);
            Diverge("GetFatAABB (bits)", qp, p.stock);
        }
        if (m_bp.GetUserData(qp) != UserData(p.serial) || m_stock.GetUserData(p.stock) != UserData(p.serial))
        {
            Diverge("GetUserData", qp, p.stock);
        }
    }

    void CheckAll()
    {
        for (int32 qp : m_live)
        {
            CompareProxy(qp, "check");
        }
        for (size_t i = 0; i + 1 < m_live.size(); i += 1 + i / 4)
        {
            const Proxy& a = m_proxy[size_t(m_live[i])];
            const Proxy& b = m_proxy[size_t(m_live[m_live.size() - 1 - i])];
            if (m_bp.TestOverlap(a.qp, b.qp) != m_stock.TestOverlap(a.stock, b.stock))
            {
                Diverge("TestOverlap", a.qp, b.qp);
            }
        }
        if (m_bp.GetProxyCount() != m_stock.GetProxyCount())
        {
            Diverge("GetProxyCount", m_bp.GetProxyCount(), m_stock.GetProxyCount());
        }
        Validate();
    }

    void Validate()
    {
        const std::string problem = quadphase::GetQuadtree(m_bp).Validate();
        ++quadphase::fuzz::g_stats.validations;
        if (!problem.empty())
        {
            std::fprintf(stderr, "box2d_fuzz: Validate: %s\n", problem.c_str());
            Diverge("the quadtree's Validate()", 1, 0);
        }
    }

    // ---- Query ----

    static bool CollectStock(void* context, int32 stockId)
    {
        static_cast<std::vector<int32_t>*>(context)->push_back(stockId);
        return true;
    }

    struct QueryCollector
    {
        std::vector<int32_t>* ids;
        int limit; // stop after this many; -1: never
        bool QueryCallback(int32 proxyId)
        {
            ids->push_back(proxyId);
            return limit < 0 || int(ids->size()) < limit;
        }
    };

    /// The quadphase ids of the proxies stock reports for `box`, sorted.
    void StockQuery(const b2AABB& box, std::vector<int32_t>& out)
    {
        out.clear();
        m_stock.Query(box, &CollectStock, &out);
        for (int32_t& id : out)
        {
            id = m_qpOfStock[size_t(id)];
        }
        std::sort(out.begin(), out.end());
    }

    void PlainQuery(const b2AABB& box)
    {
        TRACE("Query (%.9g, %.9g)-(%.9g, %.9g)", box.lowerBound.x, box.lowerBound.y, box.upperBound.x,
              box.upperBound.y);
        std::vector<int32_t>& got = m_s.ids;
        std::vector<int32_t>& want = m_s.other;
        got.clear();
        QueryCollector all{&got, -1};
        m_bp.Query(&all, box);
        std::sort(got.begin(), got.end());
        StockQuery(box, want);
        if (got != want)
        {
            PrintDifference("Query", got, want);
            Diverge("Query: proxies", long(got.size()), long(want.size()));
        }
        got.clear();
        QueryCollector first{&got, 1};
        m_bp.Query(&first, box);
        if (got.size() != (want.empty() ? 0u : 1u))
        {
            Diverge("Query: stopped after the first hit", long(got.size()), long(want.size()));
        }
    }

    void Query()
    {
        const uint8_t mode = m_in->Byte();
        const b2AABB box = ReadAABB();
        if (mode % 4 == 3)
        {
            Reentrant(box, nullptr, (mode & 4) != 0);
        }
        else
        {
            PlainQuery(box);
        }
    }

    // ---- RayCast ----

    static float CollectStockRay(void* context, const b2RayCastInput&, int32 stockId)
    {
        static_cast<std::vector<int32_t>*>(context)->push_back(stockId);
        return -1.0f;
    }

    struct RayCollector
    {
        std::vector<int32_t>* ids;
        int limit;
        float RayCastCallback(const b2RayCastInput&, int32 proxyId)
        {
            ids->push_back(proxyId);
            return (limit < 0 || int(ids->size()) < limit) ? -1.0f : 0.0f;
        }
    };

    struct ClosestHit
    {
        const Run* run;
        bool stock; // ids are stock's
        float fraction = 2.0f;
        int32 qp = -1;
        float Hit(const b2RayCastInput& input, int32 id)
        {
            const int32 q = stock ? run->m_qpOfStock[size_t(id)] : id;
            const float f = EntryFraction(run->m_proxy[size_t(q)].tight, input);
            if (f < 0.0f)
            {
                return -1.0f;
            }
            if (f < fraction)
            {
                fraction = f;
                qp = q;
            }
            return f; // clips the ray (0 ends it: a hit at the start is the closest there is)
        }
        float RayCastCallback(const b2RayCastInput& input, int32 id) { return Hit(input, id); }
        static float Stock(void* context, const b2RayCastInput& input, int32 id)
        {
            return static_cast<ClosestHit*>(context)->Hit(input, id);
        }
    };

    void StockRay(const b2RayCastInput& ray, std::vector<int32_t>& out)
    {
        out.clear();
        m_stock.RayCast(ray, &CollectStockRay, &out);
        for (int32_t& id : out)
        {
            id = m_qpOfStock[size_t(id)];
        }
        std::sort(out.begin(), out.end());
    }

    /// The proxies whose fat AABB passes b2DynamicTree::RayCast's test for a leaf, over every live proxy
    /// (sorted). This is the all-hits answer both contracts state. Stock's tree applies the same test to
    /// every ancestor first, and that test's float rounding on a large ancestor can cull a leaf that passes
    /// its own (seen with boxes 1e11 m tall): stock's answer is a subset.
    void LeafRay(const b2RayCastInput& ray, std::vector<int32_t>& out)
    {
        const LeafTest test(ray);
        out.clear();
        for (int32 qp : m_live)
        {
            if (test.Crosses(m_stock.GetFatAABB(m_proxy[size_t(qp)].stock)))
            {
                out.push_back(qp);
            }
        }
        std::sort(out.begin(), out.end());
    }

    /// True when every live fat AABB and the ray lie within 65536 m of the origin: then float rounding in the
    /// segment tests (a few ulps, under 0.03 m) stays below b2_aabbExtension, so no clipped segment can miss
    /// a shape it enters and the closest hit does not depend on the order of the walk.
    bool Bounded(const b2RayCastInput& ray) const
    {
        const float limit = quadphase::fuzz::kExactRayLimit;
        const auto in = [limit](const b2Vec2& p) {
            return std::fabs(p.x) <= limit && std::fabs(p.y) <= limit;
        };
        if (!in(ray.p1) || !in(ray.p2) || !(ray.maxFraction <= 1.0f))
        {
            return false;
        }
        for (int32 qp : m_live)
        {
            const b2AABB& fat = m_stock.GetFatAABB(m_proxy[size_t(qp)].stock);
            if (!in(fat.lowerBound) || !in(fat.upperBound))
            {
                return false;
            }
        }
        return true;
    }

    /// The proxies the segment crosses with a margin (strict_segment.h), sorted: what RayCast must report
    /// beyond kExactRayLimit.
    void StrictRay(const b2RayCastInput& ray, std::vector<int32_t>& out)
    {
        const quadphase::RayInput in{{ray.p1.x, ray.p1.y}, {ray.p2.x, ray.p2.y}, ray.maxFraction};
        out.clear();
        for (int32 qp : m_live)
        {
            if (quadphase::fuzz::StrictlyCrosses(ToBox(m_stock.GetFatAABB(m_proxy[size_t(qp)].stock)), in))
            {
                out.push_back(qp);
            }
        }
        std::sort(out.begin(), out.end());
    }

    void RayCast()
    {
        const uint8_t mode = m_in->Byte();
        const quadphase::RayInput r = quadphase::fuzz::ReadRay(*m_in);
        b2RayCastInput ray;
        ray.p1.Set(r.p1.x, r.p1.y);
        ray.p2.Set(r.p2.x, r.p2.y);
        ray.maxFraction = r.maxFraction;
        TRACE("RayCast mode %d (%.9g, %.9g)->(%.9g, %.9g) max %.9g", mode % 8, ray.p1.x, ray.p1.y, ray.p2.x,
              ray.p2.y, ray.maxFraction);
        switch (mode % 8)
        {
        case 0:
        case 1:
        case 2:
        {
            std::vector<int32_t>& got = m_s.ids;
            std::vector<int32_t>& want = m_s.other;
            std::vector<int32_t>& stock = m_s.third;
            std::vector<int32_t>& strict = m_s.fourth;
            got.clear();
            RayCollector all{&got, -1};
            m_bp.RayCast(&all, ray);
            std::sort(got.begin(), got.end());
            LeafRay(ray, want);
            StrictRay(ray, strict);
            const bool exact = Bounded(ray);
            if (exact ? got != want
                      : !(std::includes(got.begin(), got.end(), strict.begin(), strict.end()) &&
                          std::includes(want.begin(), want.end(), got.begin(), got.end())))
            {
                PrintDifference("RayCast (all hits)", got, exact ? want : strict);
                Diverge(exact
                            ? "RayCast (all hits): proxies (b2DynamicTree's leaf test)"
                            : "RayCast (all hits, beyond the exact range): a crossed proxy missed or one the "
                              "leaf test rejects reported",
                        long(got.size()), long(want.size()));
            }
            StockRay(ray, stock);
            if (!std::includes(want.begin(), want.end(), stock.begin(), stock.end()))
            {
                Diverge(
                    "RayCast (all hits): stock reports a proxy its leaf test rejects (the replica is wrong)",
                    long(want.size()), long(stock.size()));
            }
            quadphase::fuzz::g_stats.stockRayMisses += int64_t(want.size() - stock.size());
            const size_t wanted = got.empty() ? 0u : 1u;
            got.clear();
            RayCollector first{&got, 1};
            m_bp.RayCast(&first, ray);
            if (got.size() != wanted)
            {
                Diverge("RayCast: stopped after the first hit", long(got.size()), long(wanted));
            }
            break;
        }
        case 3:
        case 4:
        case 5:
        {
            ClosestHit mine{this, false};
            ClosestHit theirs{this, true};
            m_bp.RayCast(&mine, ray);
            m_stock.RayCast(ray, &ClosestHit::Stock, &theirs);
            // Ties (two shapes entered at the same fraction) may resolve to either proxy.
            if (mine.qp >= 0 && EntryFraction(m_proxy[size_t(mine.qp)].tight, ray) != mine.fraction)
            {
                Diverge("RayCast (closest hit): the proxy is not hit at the closest fraction", mine.qp,
                        theirs.qp);
            }
            if (Bounded(ray))
            {
                // The order-free answer: the nearest entry into any shape whose proxy the leaf test accepts.
                float nearest = 2.0f;
                LeafRay(ray, m_s.other);
                for (int32_t qp : m_s.other)
                {
                    const float f = EntryFraction(m_proxy[size_t(qp)].tight, ray);
                    nearest = f >= 0.0f && f < nearest ? f : nearest;
                }
                if (mine.fraction != nearest || theirs.fraction != nearest)
                {
                    Diverge("RayCast (closest hit): proxy", mine.qp, theirs.qp);
                }
            }
            break;
        }
        default:
            Reentrant(b2AABB{}, &ray, (mode & 8) != 0);
            break;
        }
    }

    // ---- re-entrant Query and RayCast ----

    enum Flag : uint8_t
    {
        kReported = 1,
        kCreated = 2,
        kMoved = 4,
        kDestroyed = 8,
        kExpected = 16, // untouched: must be reported (unless the call is stopped or clipped)
        kAllowed = 32,  // untouched: may be reported
    };

    struct Reentry
    {
        Run* run;
        b2AABB box;                // Query
        const b2RayCastInput* ray; // RayCast, or nullptr for Query
        bool clip;                 // RayCast: the callback clips the ray at each hit
        int actions = 0;
        bool stopped = false;

        bool QueryCallback(int32 id) { return run->OnReport(*this, id, nullptr) >= 0.0f; }
        float RayCastCallback(const b2RayCastInput& input, int32 id)
        {
            return run->OnReport(*this, id, &input);
        }
    };

    void Mark(int32 qp, uint8_t flag)
    {
        if (m_flags[size_t(qp)] == 0)
        {
            m_marked.push_back(qp);
        }
        m_flags[size_t(qp)] |= flag;
    }

    /// Checks one report against the contract, then lets the input choose what the callback does. Returns,
    /// for Query, >= 0 to go on and < 0 to stop; for RayCast, the callback's value.
    float OnReport(Reentry& call, int32 id, const b2RayCastInput* input)
    {
        if (!IsLive(id))
        {
            Diverge("re-entrant call: reported a proxy that is not live (destroyed during the call?)", id, 0);
        }
        const uint8_t f = m_flags[size_t(id)];
        TRACE("  reported %d (flags %d)", id, int(f));
        if ((f & kReported) != 0)
        {
            Diverge("re-entrant call: reported a proxy twice", id, 0);
        }
        Mark(id, kReported);
        const b2AABB& fat = m_stock.GetFatAABB(m_proxy[size_t(id)].stock);
        if ((f & (kCreated | kMoved)) != 0)
        {
            bool reachable;
            if (input == nullptr)
            {
                reachable = b2TestOverlap(fat, call.box);
            }
            else
            {
                reachable = LeafTest(*input).Crosses(fat);
            }
            if (!reachable)
            {
                Diverge("re-entrant call: reported a created or moved proxy that its box does not reach", id,
                        0);
            }
        }
        else if ((f & kAllowed) == 0)
        {
            Diverge("re-entrant call: reported an untouched proxy that stock does not find (Query) or the "
                    "leaf test "
                    "rejects (RayCast)",
                    id, 0);
        }
        float value = -1.0f; // go on (Query: true; RayCast: unchanged)
        if (call.clip && input != nullptr)
        {
            value = EntryFraction(m_proxy[size_t(id)].tight, *input);
        }
        if (call.actions < kMaxActionsPerCall)
        {
            ++call.actions;
            if (Act(id))
            {
                call.stopped = true;
                return input == nullptr ? -1.0f : 0.0f;
            }
        }
        return input == nullptr ? 1.0f : value;
    }

    /// One action of a re-entrant callback (`current` is the proxy being reported). Returns true to stop the
    /// call.
    bool Act(int32 current)
    {
        const uint8_t a = m_in->Byte();
        switch (a % 8)
        {
        case 3:
        {
            const int32 qp = Create(ReadAABB());
            if (qp >= 0)
            {
                Mark(qp, kCreated);
            }
            break;
        }
        case 4:
        {
            const int32 qp = (a & 8) != 0 ? current : ReadHandle();
            if (qp >= 0 && IsLive(qp))
            {
                Mark(qp, kDestroyed);
                Destroy(qp);
            }
            break;
        }
        case 5:
        {
            const int32 qp = (a & 8) != 0 ? current : ReadHandle();
            const b2AABB box = ReadAABB();
            const b2Vec2 d = ReadVector(0.05f, 4.0f);
            if (qp >= 0 && IsLive(qp))
            {
                Mark(qp, kMoved);
                MoveProxy(qp, box, d);
            }
            break;
        }
        case 6:
            PlainQuery(ReadAABB()); // a nested query, checked against stock at this moment
            break;
        case 7:
            if ((a & 8) != 0)
            {
                return true;
            }
            Touch(ReadHandle());
            break;
        default:
            break; // nothing: most reports change nothing
        }
        ++quadphase::fuzz::g_stats.reentrant;
        return false;
    }

    /// A Query (ray == nullptr) or RayCast whose callback acts on the broadphase, checked against what both
    /// contracts promise.
    void Reentrant(const b2AABB& box, const b2RayCastInput* ray, bool clip)
    {
        // Not scratch: nested queries use the scratch buffers.
        std::vector<int32_t> expected; // must be reported if untouched
        std::vector<int32_t> allowed;  // may be reported if untouched
        if (ray == nullptr)
        {
            StockQuery(box, expected);
            allowed = expected;
        }
        else
        {
            LeafRay(*ray, allowed);
            if (Bounded(*ray))
            {
                expected = allowed;
            }
            else
            {
                StrictRay(*ray, expected);
            }
        }
        for (int32_t qp : allowed)
        {
            Mark(qp, kAllowed);
        }
        for (int32_t qp : expected)
        {
            Mark(qp, kExpected);
        }
        Reentry call{this, box, ray, clip && ray != nullptr};
        TRACE("re-entrant %s (%.9g, %.9g)-(%.9g, %.9g), %zu expected", ray == nullptr ? "Query" : "RayCast",
              box.lowerBound.x, box.lowerBound.y, box.upperBound.x, box.upperBound.y, expected.size());
        if (ray == nullptr)
        {
            m_bp.Query(&call, box);
        }
        else
        {
            m_bp.RayCast(&call, *ray);
        }
        if (!call.stopped && !call.clip)
        {
            for (int32_t qp : expected)
            {
                const uint8_t f = m_flags[size_t(qp)];
                if ((f & (kCreated | kMoved | kDestroyed)) == 0 && (f & kReported) == 0)
                {
                    Diverge("re-entrant call: an untouched proxy that stock finds (Query) or the leaf test "
                            "accepts "
                            "(RayCast) was not reported",
                            qp, 0);
                }
            }
        }
        for (int32_t qp : m_marked)
        {
            m_flags[size_t(qp)] = 0;
        }
        m_marked.clear();
        if (call.actions > 0)
        {
            Validate();
        }
    }

    // ---- meta operations ----

    void Meta()
    {
        const uint8_t sub = m_in->Byte();
        TRACE("Meta %d", sub % 4);
        switch (sub % 4)
        {
        case 0:
        {
            const bool on = !quadphase::IsValidating(m_bp);
            quadphase::SetValidation(m_bp, on);
            if (quadphase::IsValidating(m_bp) != on)
            {
                Diverge("SetValidation / IsValidating", !on, on);
            }
            break;
        }
        case 1:
        {
            // Configure rebuilds the quadtree; pairs already reported are unaffected, so the next UpdatePairs
            // must still equal stock's.
            quadphase::Config c = quadphase::GetQuadtree(m_bp).GetConfig();
            const int depths[] = {-1, 0, 2, 4, 5, 6, -1, -1};
            c.depth = depths[(sub >> 2) & 7];
            c.threads = 1 + ((sub >> 5) & 1);
            c.parallelThreshold = ((sub >> 6) & 1) != 0 ? 2 : 128;
            quadphase::GetQuadtree(m_bp).Configure(c);
            break;
        }
        case 2:
            if (m_tracing)
            {
                StopTrace();
            }
            else
            {
                m_trace.Clear();
                m_expected.clear();
                quadphase::SetTrace(m_bp, &m_trace);
                m_tracing = true;
            }
            break;
        default:
            if (m_bp.GetTreeHeight() < 0 || m_bp.GetTreeBalance() < 0 || !(m_bp.GetTreeQuality() >= 0.0f))
            {
                Diverge("tree statistics", m_bp.GetTreeHeight(), m_bp.GetTreeBalance());
            }
            break;
        }
    }

    void Expect(const quadphase::TraceOp& traceOp)
    {
        if (m_tracing)
        {
            m_expected.push_back(traceOp);
        }
    }

    void StopTrace()
    {
        quadphase::SetTrace(m_bp, nullptr);
        m_tracing = false;
        const std::vector<quadphase::TraceOp>& got = m_trace.Ops();
        if (got.size() != m_expected.size())
        {
            Diverge("SetTrace: number of recorded calls", long(got.size()), long(m_expected.size()));
        }
        for (size_t i = 0; i < got.size(); ++i)
        {
            const quadphase::TraceOp& g = got[i];
            const quadphase::TraceOp& e = m_expected[i];
            const bool hasBox = e.kind == quadphase::TraceOp::Create || e.kind == quadphase::TraceOp::Move;
            const bool hasVector =
                e.kind == quadphase::TraceOp::Move || e.kind == quadphase::TraceOp::ShiftOrigin;
            if (g.kind != e.kind || (e.id >= 0 && g.id != e.id) ||
                (hasBox && std::memcmp(&g.box, &e.box, sizeof(g.box)) != 0) ||
                (hasVector && std::memcmp(&g.displacement, &e.displacement, sizeof(g.displacement)) != 0))
            {
                Diverge("SetTrace: recorded call differs", long(i), long(e.kind));
            }
        }
    }

    Scratch& m_s;
    Reader* m_in = nullptr;
    quadphase::Trace m_trace; // declared before m_bp: outlives its recording
    std::vector<quadphase::TraceOp> m_expected;
    bool m_tracing = false;
    b2BroadPhase m_bp; // quadphase's
    StockBroadPhase m_stock;
    std::vector<int32> m_live;       // quadphase ids of the live proxies, in no particular order
    std::vector<int32> m_slot;       // by quadphase id: index in m_live, or -1
    std::vector<Proxy> m_proxy;      // by quadphase id
    std::vector<int32> m_qpOfStock;  // by stock id: quadphase id, or -1
    std::vector<int32> m_qpOfSerial; // by serial: quadphase id, or -1 once destroyed
    std::vector<uint8_t> m_flags;    // by quadphase id: Flag bits during a re-entrant call
    std::vector<int32> m_marked;     // ids with flags set
    int32_t m_serials = 0;
};

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    return quadphase::fuzz::RunProgram<Run, Scratch>(data, size, &OnError);
}
