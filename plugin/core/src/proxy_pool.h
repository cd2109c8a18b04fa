// SPDX-License-Identifier: MIT
// Proxy records shared by every broadphase implementation: ids, fat boxes, user data and the move buffer.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "compiler.h"
#include "quadphase/box.h"

namespace quadphase
{

using ProxyId = int32_t;

/// Owns the proxies' fat boxes and user data, hands out ids (last freed, first reused, like b2DynamicTree's node
/// pool) and keeps the move buffer: the proxies created, moved or touched since the last LendBuffer, in call order,
/// each at most once.
///
/// The move buffer, one protocol: Buffer adds proxies (one, or many in order); FindPairs borrows the buffer with
/// LendBuffer and hands it back, emptied, with ReturnBuffer, or unchanged with RestoreBuffer when it failed.
///
/// Invariants (checked by Validate):
/// - an id is live exactly when it is not on the free list;
/// - a live proxy is flagged buffered exactly when it appears in the move buffer; it appears at most once;
/// - the live count equals the number of live ids.
class ProxyPool
{
public:
    /// Returns a new live id holding `fat` and `userData`; the proxy is not buffered.
    ProxyId Allocate(const Box& fat, void* userData);

    /// Frees a live id. Its move-buffer entry, if any, is dropped lazily by LendBuffer. Allocates nothing after
    /// ReserveFree().
    void Free(ProxyId id);

    /// Room for one more freed id, so that the next Free allocates nothing (callers reserve before they change
    /// anything, so std::bad_alloc leaves the broadphase as it was).
    void ReserveFree()
    {
        if (m_freeList.size() == m_freeList.capacity())
        {
            m_freeList.reserve(std::max<size_t>(16, 2 * m_freeList.capacity()));
        }
    }

    /// True when `id` names a live proxy.
    bool IsLive(ProxyId id) const
    {
        return id >= 0 && id < ProxyId(m_state.size()) && (m_state[size_t(id)] & kLive) != 0;
    }

    /// Reports ErrorCode::UnknownProxy naming `call` and returns false when `id` is not live.
    /// Inline: it runs on every MoveProxy; only the report is out of line.
    bool CheckLive(ProxyId id, const char* call) const
    {
        if (QUADPHASE_LIKELY(IsLive(id)))
        {
            return true;
        }
        ReportUnknown(id, call);
        return false;
    }

    /// Adds a live proxy to the move buffer unless it is already there.
    void Buffer(ProxyId id)
    {
        if (m_moveBuffer.size() == m_moveBuffer.capacity())
        {
            // may throw: nothing changed yet
            m_moveBuffer.reserve(std::max<size_t>(16, 2 * m_moveBuffer.capacity()));
        }
        if (TestAndSet(id, kBuffered))
        {
            m_moveBuffer.push_back(id);
        }
    }

    /// Buffer(id) for each of `count` live proxies, in order, without a branch on whether each is already there.
    /// Allocates nothing after ReserveBuffer(count).
    void Buffer(const ProxyId* ids, size_t count);

    /// Makes room for `more` move-buffer entries, so that the next Buffer calls adding up to that many do not
    /// allocate (for callers that must reserve before they change anything).
    void ReserveBuffer(size_t more)
    {
        if (m_moveBuffer.capacity() < m_moveBuffer.size() + more)
        {
            m_moveBuffer.reserve(std::max(m_moveBuffer.size() + more, 2 * m_moveBuffer.capacity()));
        }
    }

    /// Lends the move buffer to `work` (its previous content is dropped): the live buffered proxies, in buffer
    /// order, in the buffer's own storage (no copy). Each is flagged "in work" (see InWork). Until ReturnBuffer or
    /// RestoreBuffer no proxy may be buffered.
    void LendBuffer(std::vector<ProxyId>& work);
    /// Ends the loan: clears the "in work" flags and gives the storage back as the empty move buffer; `work` is
    /// left empty.
    void ReturnBuffer(std::vector<ProxyId>& work);
    /// Ends the loan after a failure (std::bad_alloc in FindPairs): the proxies of `work` are the move buffer
    /// again, in the same order, so the next FindPairs searches their pairs. Allocates nothing.
    void RestoreBuffer(std::vector<ProxyId>& work);

    /// Flags a proxy whose fat box changed since its cell entry was written ("stale"). Returns true when it was not
    /// flagged yet, i.e. when the caller should add it to its list of stale proxies. Like the buffered flag, the
    /// stale flag survives Free, so an id is never listed twice; ClearStale ends it.
    bool MarkStale(ProxyId id) { return TestAndSet(id, kStale); }
    void ClearStale(ProxyId id) { m_state[size_t(id)] &= uint8_t(~kStale); }
    bool IsStale(ProxyId id) const { return (m_state[size_t(id)] & kStale) != 0; }

    /// Flags a live proxy with a queued, not yet applied move (QuadtreeBroadPhase::QueueMove). Returns false when
    /// it already had one: the caller must apply the queue first, so that a proxy is queued at most once.
    bool MarkPending(ProxyId id) { return TestAndSet(id, kPending); }
    void ClearPending(ProxyId id) { m_state[size_t(id)] &= uint8_t(~kPending); }
    bool IsPending(ProxyId id) const { return (m_state[size_t(id)] & kPending) != 0; }

    /// Flags a live proxy whose bad box (non-finite or inverted) has been reported. Returns true the first time in
    /// the proxy's life (Allocate clears the flag), so that a runaway body is reported once, not once per step.
    bool MarkBadReported(ProxyId id) { return TestAndSet(id, kBadReported); }

    /// True when `id` is live and has no queued move: QuadtreeBroadPhase::QueueMove's common case, one load.
    bool IsLiveAndNotPending(ProxyId id) const
    {
        return id >= 0 && id < ProxyId(m_state.size()) && (m_state[size_t(id)] & (kLive | kPending)) == kLive;
    }

    /// The fat boxes, for loops over many ids that keep the array in a local (valid until the next Allocate).
    Box* MutableFatData() { return m_fat.data(); }
    /// The flag bytes, for loops that clear the queued-move flag of many distinct ids (ClearPending, unrolled by
    /// the caller: state[id] &= kClearPendingMask).
    uint8_t* MutableStateData() { return m_state.data(); }

    /// True while `id` is in the work list lent by LendBuffer. A pair of two such proxies is reported by the
    /// smaller id only, so that every pair is reported once.
    bool InWork(ProxyId id) const { return (m_state[size_t(id)] & kInWork) != 0; }

    const Box& Fat(ProxyId id) const { return m_fat[size_t(id)]; }
    Box& Fat(ProxyId id) { return m_fat[size_t(id)]; }
    /// The fat boxes indexed by id (valid until the next Allocate).
    const Box* FatData() const { return m_fat.data(); }
    void* UserData(ProxyId id) const { return m_userData[size_t(id)]; }

    /// Moves every live fat box by -newOrigin, with the same float operations as b2DynamicTree::ShiftOrigin.
    void ShiftOrigin(Vec2 newOrigin);

    int32_t LiveCount() const { return m_liveCount; }

    /// One past the largest id ever handed out: live ids are in [0, IdBound()).
    ProxyId IdBound() const { return ProxyId(m_state.size()); }

    /// Number of entries in the move buffer, including those of proxies destroyed since.
    int32_t BufferedCount() const { return int32_t(m_moveBuffer.size()); }

    /// Heap bytes held.
    int64_t MemoryBytes() const;

    /// Checks the invariants above. Returns an empty string when they hold, otherwise the first violation.
    std::string Validate() const;

private:
    static constexpr uint8_t kLive = 1;
    static constexpr uint8_t kBuffered = 2;
    static constexpr uint8_t kInWork = 4;
    static constexpr uint8_t kStale = 8;
    static constexpr uint8_t kPending = 16;

public:
    static constexpr uint8_t kClearPendingMask = uint8_t(~kPending);

private:
    static constexpr uint8_t kBadReported = 32;

    // Sets `flag` on `id`; true when it was not set before.
    bool TestAndSet(ProxyId id, uint8_t flag)
    {
        uint8_t& s = m_state[size_t(id)];
        const bool fresh = (s & flag) == 0;
        s |= flag;
        return fresh;
    }

    QUADPHASE_NOINLINE QUADPHASE_COLD void ReportUnknown(ProxyId id, const char* call) const;

    std::vector<Box> m_fat;
    std::vector<void*> m_userData;
    std::vector<uint8_t> m_state;
    std::vector<ProxyId> m_freeList; // stack: last freed is reused first
    std::vector<ProxyId> m_moveBuffer;
    int32_t m_liveCount = 0;
};

} // namespace quadphase
