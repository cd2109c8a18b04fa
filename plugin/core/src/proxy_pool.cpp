// SPDX-License-Identifier: MIT
// ProxyPool: id allocation, the move buffer and its loan to FindPairs, and the invariant check.
#include "proxy_pool.h"

#include <algorithm>
#include <string>

#include "report_error.h"

namespace quadphase
{

ProxyId ProxyPool::Allocate(const Box& fat, void* userData)
{
    ProxyId id;
    if (!m_freeList.empty())
    {
        id = m_freeList.back();
        m_freeList.pop_back();
        m_fat[size_t(id)] = fat;
        m_userData[size_t(id)] = userData;
        // Buffered and stale flags left by the previous owner of this id stay: its entries are still listed.
        m_state[size_t(id)] = uint8_t(kLive | (m_state[size_t(id)] & (kBuffered | kStale)));
    }
    else
    {
        // Room in all three arrays first: std::bad_alloc then leaves the pool as it was.
        const size_t n = m_state.size();
        if (n == m_state.capacity() || n == m_fat.capacity() || n == m_userData.capacity())
        {
            const size_t capacity = std::max<size_t>(16, 2 * n);
            m_fat.reserve(capacity);
            m_userData.reserve(capacity);
            m_state.reserve(capacity);
        }
        id = ProxyId(n);
        m_fat.push_back(fat);
        m_userData.push_back(userData);
        m_state.push_back(kLive);
    }
    ++m_liveCount;
    return id;
}

void ProxyPool::Free(ProxyId id)
{
    // Keep kBuffered and kStale so the id is not appended again while its old entry is still listed.
    m_state[size_t(id)] &= uint8_t(~kLive);
    m_userData[size_t(id)] = nullptr;
    m_freeList.push_back(id);
    --m_liveCount;
}

void ProxyPool::ReportUnknown(ProxyId id, const char* call) const
{
    ReportError(ErrorCode::UnknownProxy, "%s: proxy id %d is %s", call, int(id),
                (id >= 0 && id < IdBound()) ? "already destroyed" : "out of range");
}

void ProxyPool::Buffer(const ProxyId* ids, size_t count)
{
    ReserveBuffer(count); // may throw: nothing changed yet
    size_t n = m_moveBuffer.size();
    m_moveBuffer.resize(n + count); // within the capacity: no allocation
    // Locals: through the members, the compiler would reload the arrays after every flag store (a char store may
    // alias anything).
    uint8_t* const state = m_state.data();
    ProxyId* const out = m_moveBuffer.data();
    for (size_t i = 0; i < count; ++i)
    {
        // Always written, kept by advancing: whether a proxy is already buffered is close to random.
        const ProxyId id = ids[i];
        const uint8_t s = state[size_t(id)];
        state[size_t(id)] = uint8_t(s | kBuffered);
        out[n] = id;
        n += (s & kBuffered) == 0 ? 1 : 0;
    }
    m_moveBuffer.resize(n);
}

void ProxyPool::LendBuffer(std::vector<ProxyId>& work)
{
    size_t kept = 0;
    for (ProxyId id : m_moveBuffer)
    {
        uint8_t& s = m_state[size_t(id)];
        s &= uint8_t(~kBuffered);
        if ((s & kLive) != 0)
        {
            s |= kInWork;
            m_moveBuffer[kept++] = id;
        }
    }
    m_moveBuffer.resize(kept);
    work.clear();
    work.swap(m_moveBuffer);
}

void ProxyPool::ReturnBuffer(std::vector<ProxyId>& work)
{
    for (ProxyId id : work)
    {
        m_state[size_t(id)] &= uint8_t(~kInWork);
    }
    work.clear();
    work.swap(m_moveBuffer);
    work.clear(); // whatever was in the (unused) move buffer storage
}

void ProxyPool::RestoreBuffer(std::vector<ProxyId>& work)
{
    for (ProxyId id : work)
    {
        m_state[size_t(id)] = uint8_t((m_state[size_t(id)] & ~kInWork) | kBuffered);
    }
    // The move buffer holds the empty storage LendBuffer swapped in (nothing can be buffered while work is lent).
    work.swap(m_moveBuffer);
    work.clear();
}

void ProxyPool::ShiftOrigin(Vec2 newOrigin)
{
    for (ProxyId id = 0; id < IdBound(); ++id)
    {
        if (IsLive(id))
        {
            Box& b = m_fat[size_t(id)];
            b.minX -= newOrigin.x;
            b.minY -= newOrigin.y;
            b.maxX -= newOrigin.x;
            b.maxY -= newOrigin.y;
        }
    }
}

int64_t ProxyPool::MemoryBytes() const
{
    return int64_t(m_fat.capacity() * sizeof(Box) + m_userData.capacity() * sizeof(void*) +
                   m_state.capacity() + m_freeList.capacity() * sizeof(ProxyId) +
                   m_moveBuffer.capacity() * sizeof(ProxyId));
}

std::string ProxyPool::Validate() const
{
    int32_t live = 0;
    std::vector<uint8_t> onFreeList(m_state.size(), 0);
    for (ProxyId id : m_freeList)
    {
        if (id < 0 || id >= IdBound())
        {
            return "free list holds out-of-range id " + std::to_string(id);
        }
        if (onFreeList[size_t(id)]++ != 0)
        {
            return "free list holds id " + std::to_string(id) + " twice";
        }
    }
    for (ProxyId id = 0; id < IdBound(); ++id)
    {
        const bool isLive = (m_state[size_t(id)] & kLive) != 0;
        if (isLive == (onFreeList[size_t(id)] != 0))
        {
            return "id " + std::to_string(id) +
                   (isLive ? " is live and on the free list" : " is neither live nor free");
        }
        if ((m_state[size_t(id)] & kInWork) != 0)
        {
            return "id " + std::to_string(id) + " is still flagged in work outside FindPairs";
        }
        live += isLive ? 1 : 0;
    }
    if (live != m_liveCount)
    {
        return "live count " + std::to_string(m_liveCount) + " but " + std::to_string(live) + " live ids";
    }
    std::vector<uint8_t> seen(m_state.size(), 0);
    for (ProxyId id : m_moveBuffer)
    {
        if (seen[size_t(id)]++ != 0)
        {
            return "move buffer holds id " + std::to_string(id) + " twice";
        }
        if ((m_state[size_t(id)] & kBuffered) == 0)
        {
            return "id " + std::to_string(id) + " is in the move buffer but not flagged buffered";
        }
    }
    for (ProxyId id = 0; id < IdBound(); ++id)
    {
        if ((m_state[size_t(id)] & kBuffered) != 0 && seen[size_t(id)] == 0)
        {
            return "id " + std::to_string(id) + " is flagged buffered but not in the move buffer";
        }
    }
    return {};
}

} // namespace quadphase
