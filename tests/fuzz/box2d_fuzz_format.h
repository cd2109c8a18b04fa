// SPDX-License-Identifier: MIT
// The operations of the Box2D-level fuzz target (box2d_fuzz.cpp) and their opcode bytes, shared with the
// trace converter (trace_to_input.cpp) so that both read and write the same programs.
//
// Operands, in the order the target reads them (box = fuzz::ReadBox, with kRawBox for a box given bit for
// bit; vector = a mode byte, then kRawBox and two raw floats, or two 16-bit values scaled by the mode; handle
// = 16 bits, the top bit naming a quadphase id directly):
//   Create       box
//   Move         handle, flags (bit 0: shift the current box by the displacement; bit 1: compare the fat AABB
//                now), displacement vector, then the box unless bit 0
//   Destroy      handle
//   Touch        handle
//   UpdatePairs  -
//   Step         velocity vector, share byte
//   Query        mode byte, box
//   RayCast      mode byte, ray (fuzz::ReadRay)
//   ShiftOrigin  vector
//   Check        -
//   Meta         sub-operation byte
#pragma once

#include <cstdint>

namespace quadphase
{
namespace fuzz
{
namespace box2d_op
{

enum Op : uint8_t
{
    kCreate,
    kMove,
    kDestroy,
    kTouch,
    kUpdatePairs,
    kStep,
    kQuery,
    kRayCast,
    kShiftOrigin,
    kCheck,
    kMeta,
};

/// Opcode byte % 16 -> operation: moves, queries and ray casts are a game's commonest calls.
constexpr Op kTable[16] = {kCreate, kCreate, kMove,    kMove,        kMove,  kDestroy, kTouch, kUpdatePairs,
                           kStep,   kQuery,  kRayCast, kShiftOrigin, kCheck, kMeta,    kQuery, kRayCast};

/// The first opcode byte that means `op` (what the trace converter writes).
constexpr uint8_t Code(Op op)
{
    for (uint8_t i = 0; i < 16; ++i)
    {
        if (kTable[i] == op)
        {
            return i;
        }
    }
    return 0;
}

/// Vector mode byte and handle bit of values given exactly (see above).
constexpr uint16_t kDirectId = 0x8000;

} // namespace box2d_op
} // namespace fuzz
} // namespace quadphase
