// SPDX-License-Identifier: MIT
// Caller-owned records that receive a copy of every fat box the broadphase writes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "proxy_pool.h"
#include "quadphase/box.h"

namespace quadphase
{

/// Where QuadtreeBroadPhase copies each proxy's fat box whenever it changes one: the record of proxy `id` starts at
/// `base + id * stride` and begins with the box as four floats (minX, minY, maxX, maxY), Box2D's b2AABB layout.
///
/// Why: a Box2D 2.4.1 program compiled against stock headers reads fat AABBs and user data straight from
/// b2DynamicTree's node array (stock's inline b2BroadPhase::GetFatAABB, GetUserData and TestOverlap). The Box2D
/// adapter points that array at records kept current through this mirror, so those reads stay valid.
///
/// Contract: ids at or above `capacity` are skipped (the owner grows the records, then sets the mirror again).
/// Written, on the thread of the call, by the calls that change fat boxes (queued moves applied; MoveProxy;
/// ShiftOrigin), never by CreateProxy, whose record the owner writes. Until a queued move is applied, its proxy's
/// record holds the previous fat box, like GetPool().
struct BoxMirror
{
    unsigned char* base = nullptr;
    size_t stride = 0;
    int32_t capacity = 0;

    bool Enabled() const { return base != nullptr; }

    void Write(ProxyId id, const Box& box) const
    {
        if (id >= 0 && id < capacity)
        {
            // memcpy, not a cast: the records are the owner's objects (b2TreeNode), not Boxes.
            const float coords[4] = {box.minX, box.minY, box.maxX, box.maxY};
            std::memcpy(base + size_t(id) * stride, coords, sizeof coords);
        }
    }

    Box Read(ProxyId id) const
    {
        float coords[4];
        std::memcpy(coords, base + size_t(id) * stride, sizeof coords);
        return Box{coords[0], coords[1], coords[2], coords[3]};
    }
};

} // namespace quadphase
