// SPDX-License-Identifier: MIT
// A recorded sequence of broadphase calls, replayable through any broadphase (bench/ and tests use it to compare
// implementations on identical input).
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "quadphase/box.h"

namespace quadphase
{

/// One broadphase call. Ids are the recording broadphase's; a replay maps them to its own.
struct TraceOp
{
    enum Kind : uint8_t
    {
        Create,      ///< id = the id handed out; box = the shape's (tight) box
        Destroy,     ///< id
        Move,        ///< id, box = the shape's box, displacement
        Touch,       ///< id
        UpdatePairs, ///< a FindPairs / UpdatePairs call
        ShiftOrigin, ///< displacement = the new origin
    };
    Kind kind;
    int32_t id;
    Box box;
    Vec2 displacement;
};

/// A growable list of calls with a compact binary file format (little-endian, as this machine writes it).
class Trace
{
public:
    /// Appends a copy of `op` whose padding bytes (three, after `kind`) are zero, so that the same calls save to the
    /// same file, byte for byte.
    void Add(const TraceOp& op)
    {
        TraceOp clean;
        std::memset(&clean, 0, sizeof(clean));
        clean.kind = op.kind;
        clean.id = op.id;
        clean.box = op.box;
        clean.displacement = op.displacement;
        m_ops.push_back(clean);
    }
    void Clear() { m_ops.clear(); }
    const std::vector<TraceOp>& Ops() const { return m_ops; }

    /// Number of UpdatePairs calls recorded.
    int64_t UpdatePairsCount() const;

    /// Writes / reads the binary format. Return false (and leave a message in `error`) on I/O or format errors.
    bool Save(const std::string& path, std::string& error) const;
    bool Load(const std::string& path, std::string& error);

private:
    std::vector<TraceOp> m_ops;
};

} // namespace quadphase
