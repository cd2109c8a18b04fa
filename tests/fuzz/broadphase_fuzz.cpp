// SPDX-License-Identifier: MIT
// libFuzzer target: random call sequences on QuadtreeBroadPhase, each answer checked against
// BruteForceBroadPhase.
//
// The input is a byte string read as a program (tests/fuzz/fuzz_input.h). Byte 0 picks the quadtree's Config
// (fixed or automatic depth, fixed or automatic bounds; a quarter of the inputs at 2 threads, half of those
// with parallel pair generation from 2 buffered proxies). Then each operation is one opcode byte and its
// operands: create, move (MoveProxy, or QueueMove applied later), destroy, touch (ids include unknown and
// destroyed ones), update pairs, query (full, and stopped after the first hit), ray cast (all hits, stopped
// after the first, and closest hit with the callback clipping the ray), shift origin, and a check of every
// fat box, TestOverlap and the quadtree's own Validate(). Boxes come in several scales (0.01 m to 1e6 m from
// the origin, zero-size boxes) and sometimes bad (NaN, infinite, inverted). A short input is a valid program:
// reading past the end yields zeros and ends the run.
//
// What must hold (else the target prints the divergence and aborts, which libFuzzer reports as a crash):
// - same ids, same MoveProxy answers, bit-identical fat boxes, same GetProxyCount;
// - same pairs (as sets) from FindPairs, none repeated and all with a < b, leaving out proxies whose last box
// was
//   bad (the quadtree documents that those pair with nothing; the brute force does not filter them);
// - same Query and RayCast candidate sets among the sane proxies, and the same closest hit (fraction, and a
//   proxy hit at that fraction) when the callback clips the ray;
// - each unknown id reported exactly once through the error hook by the quadtree call, and a bad box once per
//   proxy life (the first bad box a proxy gets; see quadphase/error.h).
// Speed (scripts/fuzz.sh --target core): everything an operation needs is O(1) or proportional to the answer
// except the reference itself and Validate(); buffers are reused across inputs.
// Built as a fuzzer with scripts/fuzz.sh (clang-14, -fsanitize=fuzzer,address,undefined); replayed over the
// committed corpus by fuzz_replay_main.cpp in every normal test run.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "brute_force_broad_phase.h"
#include "fuzz_input.h"
#include "fuzz_stats.h"
#include "quadphase/error.h"
#include "quadtree_broad_phase.h"
#include "ray.h"
#include "strict_segment.h"

using namespace quadphase;
using quadphase::fuzz::Reader;

namespace
{

constexpr int kMaxOps = 3000;
constexpr int kMaxLive = 1500;

int g_errors = 0;
void CountError(ErrorCode, const char*, void*)
{
    ++g_errors;
}

[[noreturn]] void Diverge(const char* what, long a, long b, int op)
{
    std::fprintf(stderr, "broadphase_fuzz: DIVERGENCE at operation %d: %s (quadtree %ld, brute force %ld)\n",
                 op, what, a, b);
    std::abort();
}

/// Bit-for-bit equality (NaN included, unlike quadphase::SameBits).
bool SameBoxBits(const Box& a, const Box& b)
{
    return std::memcmp(&a, &b, sizeof(Box)) == 0;
}

/// Box2D 2.4.1's b2AABB::RayCast (slab test, same arithmetic): the fraction at which the segment enters
/// `box`, or -1 when it misses, starts inside, or enters beyond input.maxFraction.
float EntryFraction(const Box& box, const RayInput& input)
{
    float tmin = -3.402823466e+38f;
    float tmax = 3.402823466e+38f;
    const float p[2] = {input.p1.x, input.p1.y};
    const float d[2] = {input.p2.x - input.p1.x, input.p2.y - input.p1.y};
    const float lower[2] = {box.minX, box.minY};
    const float upper[2] = {box.maxX, box.maxY};
    for (int i = 0; i < 2; ++i)
    {
        if (std::fabs(d[i]) < 1.1920928955078125e-07f)
        {
            if (p[i] < lower[i] || upper[i] < p[i])
            {
                return -1.0f;
            }
        }
        else
        {
            const float inv = 1.0f / d[i];
            float t1 = (lower[i] - p[i]) * inv;
            float t2 = (upper[i] - p[i]) * inv;
            if (t1 > t2)
            {
                std::swap(t1, t2);
            }
            tmin = std::max(tmin, t1);
            tmax = std::min(tmax, t2);
            if (tmin > tmax)
            {
                return -1.0f;
            }
        }
    }
    return (tmin < 0.0f || input.maxFraction < tmin) ? -1.0f : tmin;
}

/// Reused across inputs: no allocation per operation once the buffers have grown.
struct Scratch
{
    std::vector<Pair> quadtreePairs, referencePairs;
    std::vector<ProxyId> quadtreeIds, referenceIds, firstIds;
};

struct Collector
{
    std::vector<ProxyId>* ids;
    int limit = -1; // stop after this many (Query) or return 0 after this many (RayCast); -1: never
    static bool Query(void* context, ProxyId id)
    {
        auto* self = static_cast<Collector*>(context);
        self->ids->push_back(id);
        return self->limit < 0 || int(self->ids->size()) < self->limit;
    }
    static float Ray(void* context, const RayInput&, ProxyId id)
    {
        auto* self = static_cast<Collector*>(context);
        self->ids->push_back(id);
        return (self->limit < 0 || int(self->ids->size()) < self->limit) ? -1.0f : 0.0f;
    }
};

/// Closest-hit ray cast: a proxy is hit where the segment enters its tight box (strictly inside its fat box),
/// and the callback clips the ray there, as b2World::RayCast's closest-hit callbacks do.
struct ClosestHit
{
    const std::vector<Box>* tight; // by id
    const std::vector<bool>* sane; // by id
    float fraction = 2.0f;         // none yet
    ProxyId id = -1;
    static float Ray(void* context, const RayInput& input, ProxyId id)
    {
        auto* self = static_cast<ClosestHit*>(context);
        if (!(*self->sane)[size_t(id)])
        {
            return -1.0f;
        }
        const float f = EntryFraction((*self->tight)[size_t(id)], input);
        if (f < 0.0f)
        {
            return -1.0f;
        }
        if (f < self->fraction || (f == self->fraction && id < self->id))
        {
            self->fraction = f;
            self->id = id;
        }
        return f;
    }
};

class Run
{
public:
    Run(uint8_t configByte, Scratch& scratch) : m_qt(FatPolicy{}, MakeConfig(configByte)), m_s(scratch) {}

    void Execute(Reader& in)
    {
        for (m_op = 0; m_op < kMaxOps && !in.Done(); ++m_op)
        {
            switch (in.Byte() % 10)
            {
            case 0:
            case 1:
                Create(in);
                break;
            case 2:
            case 3:
                Move(in);
                break;
            case 4:
                Destroy(in);
                break;
            case 5:
                Touch(in);
                break;
            case 6:
                FindPairs();
                break;
            case 7:
                Query(in);
                break;
            case 8:
                RayCast(in);
                break;
            default:
                if (in.Byte() % 4 == 0)
                {
                    ShiftOrigin(in);
                }
                else
                {
                    CheckAll();
                }
                break;
            }
        }
        FindPairs();
        CheckAll();
        fuzz::g_stats.operations += m_op;
    }

private:
    static Config MakeConfig(uint8_t b)
    {
        Config c;
        c.depth = int(b % 8) - 1; // automatic, or 0..6
        c.autoBounds = ((b >> 3) & 1) == 0;
        c.bounds = Box{-64.0f, -64.0f, 64.0f, 64.0f};
        // A quarter of the inputs at 2 threads (parallel regions cost a wake-up of the other thread each, the
        // largest cost of an input), half of those with the parallel paths taken from 2 buffered proxies.
        c.threads = ((b >> 4) & 3) == 3 ? 2 : 1;
        c.parallelThreshold = ((b >> 6) & 1) != 0 ? 2 : 128;
        return c;
    }

    Box ReadBox(Reader& in, bool& sane) { return fuzz::ReadBox(in, true, sane); }

    ProxyId ReadId(Reader& in)
    {
        const uint16_t v = in.U16();
        if ((v & 0x8000) != 0 || m_live.empty())
        {
            return ProxyId(int(v & 0x7fff) - 16); // anything: negative, destroyed, never created, live
        }
        return m_live[size_t(v) % m_live.size()];
    }

    bool IsLive(ProxyId id) const
    {
        return id >= 0 && size_t(id) < m_index.size() && m_index[size_t(id)] >= 0;
    }

    void Expect(int reports, const char* call)
    {
        if (g_errors != reports)
        {
            Diverge(call, g_errors, reports, m_op);
        }
        g_errors = 0;
    }

    /// Makes `call` (DestroyProxy or TouchProxy of one id) on the quadtree, which must report the id once unless
    /// it is `live`, then on the brute force, whose reports are not counted.
    template <typename Call>
    void OnBoth(bool live, const char* what, Call call)
    {
        g_errors = 0;
        call(m_qt);
        Expect(live ? 0 : 1, what);
        call(m_bf);
        g_errors = 0;
    }

    void Create(Reader& in)
    {
        if (int(m_live.size()) >= kMaxLive)
        {
            return;
        }
        bool sane = true;
        const Box b = ReadBox(in, sane);
        g_errors = 0;
        const ProxyId a = m_qt.CreateProxy(b, nullptr);
        Expect(sane ? 0 : 1, "CreateProxy: error reports");
        const ProxyId r = m_bf.CreateProxy(b, nullptr);
        g_errors = 0;
        if (a != r)
        {
            Diverge("CreateProxy: ids", a, r, m_op);
        }
        Track(a);
        m_index[size_t(a)] = int32_t(m_live.size());
        m_live.push_back(a);
        m_sane[size_t(a)] = sane;
        m_tight[size_t(a)] = b;
        m_badReported[size_t(a)] = !sane;
        CompareFat(a, "CreateProxy: fat box");
    }

    void Move(Reader& in)
    {
        const ProxyId id = ReadId(in);
        bool sane = true;
        Box b = ReadBox(in, sane);
        Vec2 d{in.Signed() * 4.0f, in.Signed() * 4.0f};
        const uint8_t flags = in.Byte();
        const bool live = IsLive(id);
        if (live && (flags & 1) != 0 && m_sane[size_t(id)] && sane)
        {
            // a small move of the current box: often stays inside the fat box. The reference's box, so that
            // queued moves stay queued.
            const Box& f = m_bf.GetFatBox(id);
            d = Vec2{d.x * 0.01f, d.y * 0.01f};
            b = Box{f.minX + 0.1f + d.x, f.minY + 0.1f + d.y, f.maxX - 0.1f + d.x, f.maxY - 0.1f + d.y};
            if (!IsOrdered(b))
            {
                b = Box{b.minX, b.minY, b.minX, b.minY};
            }
        }
        const bool reportBad = live && !sane && !m_badReported[size_t(id)];
        const bool queue = (flags & 2) != 0;
        g_errors = 0;
        bool a = false;
        if (queue)
        {
            m_qt.QueueMove(id, b, d); // applied by the next call that reads a fat box or the pairs
        }
        else
        {
            a = m_qt.MoveProxy(id, b, d);
        }
        Expect((live ? 0 : 1) + (reportBad ? 1 : 0),
               queue ? "QueueMove: error reports" : "MoveProxy: error reports");
        const bool r = m_bf.MoveProxy(id, b, d);
        g_errors = 0;
        if (!queue && a != r)
        {
            Diverge("MoveProxy: answer", a, r, m_op);
        }
        if (live)
        {
            m_badReported[size_t(id)] = m_badReported[size_t(id)] || reportBad;
            m_sane[size_t(id)] = sane;
            m_tight[size_t(id)] = b;
            if (!queue)
            {
                CompareFat(id, "MoveProxy: fat box");
            }
        }
    }

    void Destroy(Reader& in)
    {
        const ProxyId id = ReadId(in);
        const bool live = IsLive(id);
        OnBoth(live, "DestroyProxy: error reports", [id](auto& bp) { bp.DestroyProxy(id); });
        if (live)
        {
            // swap-remove: O(1)
            const int32_t slot = m_index[size_t(id)];
            m_live[size_t(slot)] = m_live.back();
            m_index[size_t(m_live[size_t(slot)])] = slot;
            m_live.pop_back();
            m_index[size_t(id)] = -1;
        }
        if (m_qt.GetProxyCount() != m_bf.GetProxyCount() || m_qt.GetProxyCount() != int32_t(m_live.size()))
        {
            Diverge("DestroyProxy: proxy count", m_qt.GetProxyCount(), m_bf.GetProxyCount(), m_op);
        }
    }

    void Touch(Reader& in)
    {
        const ProxyId id = ReadId(in);
        OnBoth(IsLive(id), "TouchProxy: error reports", [id](auto& bp) { bp.TouchProxy(id); });
    }

    /// Drops the pairs of proxies whose last box was bad; the order is kept.
    void DropInsane(std::vector<Pair>& pairs) const
    {
        pairs.erase(
            std::remove_if(pairs.begin(), pairs.end(),
                           [this](const Pair& p) { return !m_sane[size_t(p.a)] || !m_sane[size_t(p.b)]; }),
            pairs.end());
    }

    void SaneOnly(std::vector<ProxyId>& ids) const
    {
        ids.erase(std::remove_if(ids.begin(), ids.end(), [this](ProxyId id) { return !m_sane[size_t(id)]; }),
                  ids.end());
        std::sort(ids.begin(), ids.end());
    }

    void FindPairs()
    {
        std::vector<Pair>& a = m_s.quadtreePairs;
        std::vector<Pair>& r = m_s.referencePairs;
        a.clear();
        r.clear();
        m_qt.FindPairs(a);
        m_bf.FindPairs(r);
        std::sort(a.begin(), a.end());
        if (std::adjacent_find(a.begin(), a.end()) != a.end())
        {
            Diverge("FindPairs: a pair reported twice", long(a.size()), long(r.size()), m_op);
        }
        for (const Pair& p : a)
        {
            if (!(p.a < p.b) || !IsLive(p.a) || !IsLive(p.b))
            {
                Diverge("FindPairs: pair not ordered or not live", p.a, p.b, m_op);
            }
        }
        DropInsane(a); // keeps the order
        DropInsane(r);
        std::sort(r.begin(), r.end());
        if (a != r)
        {
            Diverge("FindPairs: pair sets (sane proxies)", long(a.size()), long(r.size()), m_op);
        }
    }

    Box ReadQueryBox(Reader& in)
    {
        bool sane = true;
        Box b = ReadBox(in, sane);
        if (!sane)
        {
            b = Box{-1.0f, -1.0f, 1.0f, 1.0f};
        }
        return b;
    }

    /// One Query or RayCast, call(broadphase, collector), on both broadphases: leaves the candidates that are
    /// sane proxies in a and r, and checks that the quadtree, stopped after its first candidate, calls back
    /// once, and only when it has a candidate (else Diverge with `stopped`).
    template <typename Call>
    void CollectBoth(const char* stopped, Collector& a, Collector& r, Call call)
    {
        a.ids->clear();
        r.ids->clear();
        call(m_qt, a);
        call(m_bf, r);
        const bool any = !a.ids->empty();
        SaneOnly(*a.ids);
        SaneOnly(*r.ids);
        m_s.firstIds.clear();
        Collector first{&m_s.firstIds, 1};
        call(m_qt, first);
        if (first.ids->size() != (any ? 1u : 0u))
        {
            Diverge(stopped, long(first.ids->size()), long(any), m_op);
        }
    }

    void Query(Reader& in)
    {
        const Box box = ReadQueryBox(in);
        Collector a{&m_s.quadtreeIds}, r{&m_s.referenceIds};
        CollectBoth("Query: stop after the first candidate", a, r,
                    [&](auto& bp, Collector& c) { bp.Query(box, &Collector::Query, &c); });
        if (*a.ids != *r.ids)
        {
            Diverge("Query: candidate sets (sane proxies)", long(a.ids->size()), long(r.ids->size()), m_op);
        }
    }

    void RayCast(Reader& in)
    {
        const RayInput ray = fuzz::ReadRay(in);
        Collector a{&m_s.quadtreeIds}, r{&m_s.referenceIds};
        CollectBoth("RayCast: stop after the first candidate", a, r,
                    [&](auto& bp, Collector& c) { bp.RayCast(ray, &Collector::Ray, &c); });
        const bool exact = Bounded();
        if (exact ? *a.ids != *r.ids
                  : !(std::includes(r.ids->begin(), r.ids->end(), a.ids->begin(), a.ids->end()) &&
                      StrictlyCrossedReported(ray, *a.ids)))
        {
            Diverge(exact
                        ? "RayCast: candidate sets (sane proxies)"
                        : "RayCast beyond the exact range: a crossed proxy missed or a rejected one reported",
                    long(a.ids->size()), long(r.ids->size()), m_op);
        }
        // Closest hit: the clipped walk must find the same nearest entry as the reference's full scan. Ties
        // (two tight boxes entered at the same fraction) may resolve to either proxy: the one reported must
        // be hit at that fraction.
        ClosestHit qc{&m_tight, &m_sane}, rc{&m_tight, &m_sane};
        m_qt.RayCast(ray, &ClosestHit::Ray, &qc);
        m_bf.RayCast(ray, &ClosestHit::Ray, &rc);
        if (exact &&
            qc.fraction != rc.fraction) // beyond the exact range the walk's order decides (strict_segment.h)
        {
            Diverge("RayCast: closest hit (proxy)", qc.id, rc.id, m_op);
        }
        if (qc.id >= 0 && EntryFraction(m_tight[size_t(qc.id)], ray) != qc.fraction)
        {
            Diverge("RayCast: closest hit not hit at its fraction", qc.id, rc.id, m_op);
        }
    }

    /// True when every sane live fat box lies within fuzz::kExactRayLimit of the origin (the rays always do):
    /// RayCast is then compared with the brute force exactly (strict_segment.h).
    bool Bounded() const
    {
        const float limit = fuzz::kExactRayLimit;
        for (ProxyId id : m_live)
        {
            const Box& b = m_bf.GetFatBox(id);
            if (m_sane[size_t(id)] && !(std::fabs(b.minX) <= limit && std::fabs(b.minY) <= limit &&
                                        std::fabs(b.maxX) <= limit && std::fabs(b.maxY) <= limit))
            {
                return false;
            }
        }
        return true;
    }

    /// Every sane live proxy the segment crosses with a margin is among `reported` (sorted).
    bool StrictlyCrossedReported(const RayInput& ray, const std::vector<ProxyId>& reported) const
    {
        for (ProxyId id : m_live)
        {
            if (m_sane[size_t(id)] && fuzz::StrictlyCrosses(m_bf.GetFatBox(id), ray) &&
                !std::binary_search(reported.begin(), reported.end(), id))
            {
                return false;
            }
        }
        return true;
    }

    void ShiftOrigin(Reader& in)
    {
        const float scale = (in.Byte() & 1) != 0 ? 1.0e5f : 16.0f;
        const Vec2 origin{in.Signed() * scale, in.Signed() * scale};
        m_qt.ShiftOrigin(origin);
        m_bf.ShiftOrigin(origin);
        for (ProxyId id : m_live)
        {
            Box& t = m_tight[size_t(id)];
            t = Box{t.minX - origin.x, t.minY - origin.y, t.maxX - origin.x, t.maxY - origin.y};
        }
        CheckAll();
    }

    void CheckAll()
    {
        for (ProxyId id : m_live)
        {
            CompareFat(id, "fat box");
        }
        if (m_live.size() >= 2)
        {
            const ProxyId p = m_live.front();
            const ProxyId q = m_live.back();
            const bool expected =
                m_sane[size_t(p)] && m_sane[size_t(q)] && Overlaps(m_bf.GetFatBox(p), m_bf.GetFatBox(q));
            const bool got = m_qt.TestOverlap(p, q);
            if (m_sane[size_t(p)] && m_sane[size_t(q)] && got != expected)
            {
                Diverge("TestOverlap", got, expected, m_op);
            }
        }
        if (m_qt.GetProxyCount() != m_bf.GetProxyCount())
        {
            Diverge("GetProxyCount", m_qt.GetProxyCount(), m_bf.GetProxyCount(), m_op);
        }
        const std::string problem = m_qt.Validate();
        ++fuzz::g_stats.validations;
        if (!problem.empty())
        {
            std::fprintf(stderr, "broadphase_fuzz: Validate: %s\n", problem.c_str());
            Diverge("Validate", 1, 0, m_op);
        }
    }

    void CompareFat(ProxyId id, const char* what)
    {
        if (!SameBoxBits(m_qt.GetFatBox(id), m_bf.GetFatBox(id)))
        {
            Diverge(what, id, id, m_op);
        }
    }

    void Track(ProxyId id)
    {
        if (size_t(id) >= m_index.size())
        {
            const size_t n = size_t(id) + 1;
            m_index.resize(n, -1);
            m_sane.resize(n, true);
            m_badReported.resize(n, false);
            m_tight.resize(n, Box{0.0f, 0.0f, 0.0f, 0.0f});
        }
    }

    QuadtreeBroadPhase m_qt;
    BruteForceBroadPhase m_bf;
    Scratch& m_s;
    std::vector<ProxyId> m_live;     // live ids, in no particular order
    std::vector<int32_t> m_index;    // by id: slot in m_live, or -1 when not live
    std::vector<bool> m_sane;        // by id: the last box given was finite and ordered
    std::vector<bool> m_badReported; // by id: a bad box was reported in this proxy's life (once per life)
    std::vector<Box> m_tight;        // by id: the last tight box given (the closest-hit callback's shape)
    int m_op = 0;
};

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    return quadphase::fuzz::RunProgram<Run, Scratch>(data, size, &CountError);
}
