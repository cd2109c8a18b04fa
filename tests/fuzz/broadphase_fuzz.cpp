// libFuzzer target: random call sequences on QuadtreeBroadPhase, each answer checked against
// BruteForceBroadPhase.
//
// The input is a byte string read as a program. Byte 0 picks the quadtree's Config (fixed or automatic depth,
// fixed or automatic bounds, 1 or 2 threads, parallel pair generation from 2 buffered proxies or the
// default). Then each operation is one opcode byte and its operands: create, move, destroy, touch (ids
// include unknown and destroyed ones), update pairs, query (full, and stopped after the first hit), ray cast,
// shift origin, and a check of every fat box, TestOverlap and the quadtree's own Validate(). Boxes come in
// several scales (0.01 m to 1e6 m from the origin, zero-size boxes) and sometimes bad (NaN, infinite,
// inverted). A short input is a valid program: reading past the end yields zeros and ends the run.
//
// What must hold (else the target prints the divergence and aborts, which libFuzzer reports as a crash):
// - same ids, same MoveProxy answers, bit-identical fat boxes, same GetProxyCount;
// - same pairs (as sets) from FindPairs, none repeated and all with a < b, leaving out proxies whose last box
// was
//   bad (the quadtree documents that those pair with nothing; the brute force does not filter them);
// - same Query and RayCast candidate sets among the sane proxies;
// - each unknown id reported exactly once through the error hook by the quadtree call, and a bad box once per
//   proxy life (the first bad box a proxy gets; see quadphase/error.h).
// Built as a fuzzer with scripts/fuzz.sh (clang-14, -fsanitize=fuzzer,address,undefined); replayed over the
// committed corpus by fuzz_replay_main.cpp in every normal test run.
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

#include "quadphase/brute_force_broad_phase.h"
#include "quadphase/error.h"
#include "quadphase/quadtree_broad_phase.h"
#include "quadphase/ray.h"

using namespace quadphase;

namespace
{

constexpr int kMaxOps = 3000;
constexpr int kMaxLive = 1500;

class Reader
{
public:
    Reader(const uint8_t* data, size_t size) : m_data(data), m_size(size) {}
    bool Done() const { return m_pos >= m_size; }
    uint8_t Byte() { return m_pos < m_size ? m_data[m_pos++] : 0; }
    uint16_t U16()
    {
        const uint16_t lo = Byte();
        return uint16_t(lo | (uint16_t(Byte()) << 8));
    }
    /// In [-1, 1].
    float Signed() { return float(int(U16()) - 32768) / 32768.0f; }
    /// In [0, 1].
    float Unit() { return float(U16()) / 65535.0f; }

private:
    const uint8_t* m_data;
    size_t m_size;
    size_t m_pos = 0;
};

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

struct Collector
{
    std::vector<ProxyId> ids;
    int limit = -1; // stop after this many (Query) or return 0 after this many (RayCast); -1: never
    static bool Query(void* context, ProxyId id)
    {
        auto* self = static_cast<Collector*>(context);
        self->ids.push_back(id);
        return self->limit < 0 || int(self->ids.size()) < self->limit;
    }
    static float Ray(void* context, const RayInput&, ProxyId id)
    {
        auto* self = static_cast<Collector*>(context);
        self->ids.push_back(id);
        return (self->limit < 0 || int(self->ids.size()) < self->limit) ? -1.0f : 0.0f;
    }
};

class Run
{
public:
    explicit Run(uint8_t configByte) : m_qt(FatPolicy{}, MakeConfig(configByte)) {}

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
    }

private:
    static Config MakeConfig(uint8_t b)
    {
        Config c;
        c.depth = int(b % 8) - 1; // automatic, or 0..6
        c.autoBounds = ((b >> 3) & 1) == 0;
        c.bounds = Box{-64.0f, -64.0f, 64.0f, 64.0f};
        c.threads = 1 + ((b >> 4) & 1);
        c.parallelThreshold = ((b >> 5) & 1) != 0 ? 2 : 128;
        return c;
    }

    /// A tight box; `sane` tells whether it is finite and ordered.
    Box ReadBox(Reader& in, bool& sane)
    {
        const uint8_t mode = in.Byte();
        const float scales[] = {8.0f, 64.0f, 1000.0f, 1.0e5f, 1.0e6f, 0.5f};
        const float centreScale = scales[(mode >> 4) % 6];
        const float cx = in.Signed() * centreScale;
        const float cy = in.Signed() * centreScale;
        float hx = in.Unit() * ((mode & 1) != 0 ? 20.0f : 2.0f);
        float hy = in.Unit() * ((mode & 2) != 0 ? 20.0f : 2.0f);
        if ((mode & 12) == 12)
        {
            hx = 0.0f; // zero-size (on one axis or both)
            hy = (mode & 64) != 0 ? 0.0f : hy;
        }
        Box b{cx - hx, cy - hy, cx + hx, cy + hy};
        sane = true;
        if (mode == 0xff || mode == 0xfe) // bad boxes: about one in a hundred
        {
            const float nan = std::numeric_limits<float>::quiet_NaN();
            const float inf = std::numeric_limits<float>::infinity();
            switch (in.Byte() % 4)
            {
            case 0:
                b.minX = nan;
                break;
            case 1:
                b.maxY = inf;
                break;
            case 2:
                b = Box{-inf, -inf, inf, inf};
                break;
            default:
                b = Box{b.maxX + 1.0f, b.minY, b.minX, b.maxY}; // inverted on x
                break;
            }
            sane = false;
        }
        return b;
    }

    ProxyId ReadId(Reader& in)
    {
        const uint16_t v = in.U16();
        if ((v & 0x8000) != 0 || m_live.empty())
        {
            return ProxyId(int(v & 0x7fff) - 16); // anything: negative, destroyed, never created, live
        }
        return m_live[size_t(v) % m_live.size()];
    }

    bool IsLive(ProxyId id) const { return std::find(m_live.begin(), m_live.end(), id) != m_live.end(); }

    void Expect(int reports, const char* call)
    {
        if (g_errors != reports)
        {
            Diverge(call, g_errors, reports, m_op);
        }
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
        m_live.push_back(a);
        SetSane(a, sane);
        m_badReported[size_t(a)] = !sane;
        CompareFat(a, "CreateProxy: fat box");
    }

    void Move(Reader& in)
    {
        const ProxyId id = ReadId(in);
        bool sane = true;
        Box b = ReadBox(in, sane);
        Vec2 d{in.Signed() * 4.0f, in.Signed() * 4.0f};
        if (IsLive(id) && (in.Byte() & 1) != 0 && m_sane[size_t(id)] && sane)
        {
            // a small move of the current box: often stays inside the fat box
            const Box& f = m_qt.GetFatBox(id);
            d = Vec2{d.x * 0.01f, d.y * 0.01f};
            b = Box{f.minX + 0.1f + d.x, f.minY + 0.1f + d.y, f.maxX - 0.1f + d.x, f.maxY - 0.1f + d.y};
            if (!IsOrdered(b))
            {
                b = Box{b.minX, b.minY, b.minX, b.minY};
            }
        }
        const bool live = IsLive(id);
        const bool reportBad = live && !sane && !m_badReported[size_t(id)];
        g_errors = 0;
        const bool a = m_qt.MoveProxy(id, b, d);
        Expect((live ? 0 : 1) + (reportBad ? 1 : 0), "MoveProxy: error reports");
        if (reportBad)
        {
            m_badReported[size_t(id)] = true;
        }
        const bool r = m_bf.MoveProxy(id, b, d);
        g_errors = 0;
        if (a != r)
        {
            Diverge("MoveProxy: answer", a, r, m_op);
        }
        if (live)
        {
            SetSane(id, sane);
            CompareFat(id, "MoveProxy: fat box");
        }
    }

    void Destroy(Reader& in)
    {
        const ProxyId id = ReadId(in);
        const bool live = IsLive(id);
        g_errors = 0;
        m_qt.DestroyProxy(id);
        Expect(live ? 0 : 1, "DestroyProxy: error reports");
        m_bf.DestroyProxy(id);
        g_errors = 0;
        if (live)
        {
            m_live.erase(std::find(m_live.begin(), m_live.end(), id));
        }
        if (m_qt.GetProxyCount() != m_bf.GetProxyCount() || m_qt.GetProxyCount() != int32_t(m_live.size()))
        {
            Diverge("DestroyProxy: proxy count", m_qt.GetProxyCount(), m_bf.GetProxyCount(), m_op);
        }
    }

    void Touch(Reader& in)
    {
        const ProxyId id = ReadId(in);
        const bool live = IsLive(id);
        g_errors = 0;
        m_qt.TouchProxy(id);
        Expect(live ? 0 : 1, "TouchProxy: error reports");
        m_bf.TouchProxy(id);
        g_errors = 0;
    }

    std::vector<Pair> SaneOnly(std::vector<Pair> pairs) const
    {
        pairs.erase(std::remove_if(pairs.begin(), pairs.end(),
                                   [this](const Pair& p)
                                   { return !m_sane[size_t(p.a)] || !m_sane[size_t(p.b)]; }),
                    pairs.end());
        std::sort(pairs.begin(), pairs.end());
        return pairs;
    }

    std::vector<ProxyId> SaneOnly(std::vector<ProxyId> ids) const
    {
        ids.erase(std::remove_if(ids.begin(), ids.end(), [this](ProxyId id) { return !m_sane[size_t(id)]; }),
                  ids.end());
        std::sort(ids.begin(), ids.end());
        return ids;
    }

    void FindPairs()
    {
        std::vector<Pair> a, r;
        m_qt.FindPairs(a);
        m_bf.FindPairs(r);
        std::vector<Pair> all = a;
        std::sort(all.begin(), all.end());
        if (std::adjacent_find(all.begin(), all.end()) != all.end())
        {
            Diverge("FindPairs: a pair reported twice", long(a.size()), long(r.size()), m_op);
        }
        for (const Pair& p : all)
        {
            if (!(p.a < p.b) || !IsLive(p.a) || !IsLive(p.b))
            {
                Diverge("FindPairs: pair not ordered or not live", p.a, p.b, m_op);
            }
        }
        const std::vector<Pair> sa = SaneOnly(a);
        const std::vector<Pair> sr = SaneOnly(r);
        if (sa != sr)
        {
            Diverge("FindPairs: pair sets (sane proxies)", long(sa.size()), long(sr.size()), m_op);
        }
        m_pairsCompared += int64_t(sr.size());
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

    void Query(Reader& in)
    {
        const Box box = ReadQueryBox(in);
        Collector a, r;
        m_qt.Query(box, &Collector::Query, &a);
        m_bf.Query(box, &Collector::Query, &r);
        if (SaneOnly(a.ids) != SaneOnly(r.ids))
        {
            Diverge("Query: candidate sets (sane proxies)", long(a.ids.size()), long(r.ids.size()), m_op);
        }
        // stopped after the first candidate: one call, and only when there is a candidate
        Collector first;
        first.limit = 1;
        m_qt.Query(box, &Collector::Query, &first);
        if (first.ids.size() != (a.ids.empty() ? 0u : 1u))
        {
            Diverge("Query: stop after the first candidate", long(first.ids.size()), long(a.ids.size()),
                    m_op);
        }
    }

    void RayCast(Reader& in)
    {
        const uint8_t mode = in.Byte();
        const float scale = (mode & 1) != 0 ? 1000.0f : 64.0f;
        RayInput ray{{in.Signed() * scale, in.Signed() * scale},
                     {in.Signed() * scale, in.Signed() * scale},
                     in.Unit() * 1.5f};
        if (ray.p1.x == ray.p2.x && ray.p1.y == ray.p2.y)
        {
            ray.p2.x += 1.0f; // Box2D requires p1 != p2
        }
        Collector a, r;
        m_qt.RayCast(ray, &Collector::Ray, &a);
        m_bf.RayCast(ray, &Collector::Ray, &r);
        if (SaneOnly(a.ids) != SaneOnly(r.ids))
        {
            Diverge("RayCast: candidate sets (sane proxies)", long(a.ids.size()), long(r.ids.size()), m_op);
        }
        Collector first;
        first.limit = 1;
        m_qt.RayCast(ray, &Collector::Ray, &first);
        if (first.ids.size() != (a.ids.empty() ? 0u : 1u))
        {
            Diverge("RayCast: stop after the first candidate", long(first.ids.size()), long(a.ids.size()),
                    m_op);
        }
    }

    void ShiftOrigin(Reader& in)
    {
        const float scale = (in.Byte() & 1) != 0 ? 1.0e5f : 16.0f;
        const Vec2 origin{in.Signed() * scale, in.Signed() * scale};
        m_qt.ShiftOrigin(origin);
        m_bf.ShiftOrigin(origin);
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

    void SetSane(ProxyId id, bool sane)
    {
        if (size_t(id) >= m_sane.size())
        {
            m_sane.resize(size_t(id) + 1, true);
            m_badReported.resize(size_t(id) + 1, false);
        }
        m_sane[size_t(id)] = sane;
    }

    QuadtreeBroadPhase m_qt;
    BruteForceBroadPhase m_bf;
    std::vector<ProxyId> m_live;
    std::vector<bool> m_sane; // by id: the last box given was finite and ordered
    std::vector<bool> m_badReported; // by id: a bad box was reported in this proxy's life (once per life)
    int m_op = 0;
    int64_t m_pairsCompared = 0;
};

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size == 0)
    {
        return 0;
    }
    const ErrorHandler previous = SetErrorHandler(&CountError);
    Reader in(data, size);
    Run run(in.Byte());
    run.Execute(in);
    SetErrorHandler(previous);
    return 0;
}
