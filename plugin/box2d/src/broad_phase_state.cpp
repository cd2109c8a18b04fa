// SPDX-License-Identifier: MIT
// The state behind b2BroadPhase's opaque pointer: its block, its modes and the list of its observers.
#include "broad_phase_state.h"

#include <cstdlib>

#include "box2d_types.h"
#include "environment.h"
#include "quadphase/box2d.h"
#include "trace_observer.h"
#include "validation_observer.h"

namespace quadphase
{
namespace detail
{
namespace
{

void* NewStateBlock(BroadPhaseState* state, int32 capacity)
{
    // One int32 more than the capacity: b2BroadPhase keeps block + kStateHeader, which must point into the block and
    // not one past its end (capacity 0), or leak checkers (LeakSanitizer, Valgrind) do not see the state reachable
    // from a live world and report it, and all it holds, as leaked.
    unsigned char* block =
        static_cast<unsigned char*>(b2Alloc(int32(kStateHeader) + (capacity + 1) * int32(sizeof(int32))));
    std::memcpy(block, &state, sizeof state);
    SetFastMovesAt(block + kStateHeader, state->FastMoves());
    return block + kStateHeader;
}

void FreeStateBlock(void* block)
{
    b2Free(static_cast<unsigned char*>(block) - kStateHeader);
}

} // namespace

BroadPhaseState::BroadPhaseState(const StockMembers& members, bool withStockTree)
    : core(Box2DFatPolicy()), records(withStockTree ? nullptr : &members),
      stockTree(withStockTree ? new StockTreeMode(members) : nullptr), m_block(members.state)
{
    ListObservers();
}

void BroadPhaseState::SetTrace(Trace* recording)
{
    trace = recording != nullptr ? NewTraceObserver(*recording) : nullptr;
    ListObservers();
}

void BroadPhaseState::SetValidation(bool enabled)
{
    if (enabled != (validation != nullptr))
    {
        validation = enabled ? NewValidationObserver(core) : nullptr;
        ListObservers();
    }
}

void BroadPhaseState::ListObservers()
{
    std::vector<BroadPhaseObserver*> list;
    for (BroadPhaseObserver* observer :
         {static_cast<BroadPhaseObserver*>(stockTree.get()), trace.get(), validation.get()})
    {
        if (observer != nullptr)
        {
            list.push_back(observer);
        }
    }
    observers.Assign(std::move(list));
    if (*m_block != nullptr) // null while NewState builds the state
    {
        SetFastMovesAt(*m_block, FastMoves());
    }
}

void NewState(const StockMembers& members)
{
    *members.moveCapacity = *members.moveCount = *members.pairCapacity = *members.pairCount = 0;
    *members.pairBuffer = nullptr; // stock-tree mode's constructor gives stock's buffers
    *members.state = nullptr;
    std::unique_ptr<BroadPhaseState> state(
        new BroadPhaseState(members, EnvironmentFlag("QUADPHASE_STOCK_TREE")));
    state->SetValidation(EnvironmentFlag("QUADPHASE_VALIDATE"));
    *members.state = NewStateBlock(state.release(), *members.moveCapacity);
}

void DeleteState(void* block)
{
    delete &StateAt(block);
    FreeStateBlock(block);
}

void* GrowStateBlock(void* block, int32 count, int32 capacity)
{
    void* grown = NewStateBlock(&StateAt(block), capacity);
    std::memcpy(grown, block, size_t(count) * sizeof(int32));
    FreeStateBlock(block);
    return grown;
}

BroadPhaseState& StateOf(b2BroadPhase& broadPhase)
{
    void* block;
    std::memcpy(&block, reinterpret_cast<unsigned char*>(&broadPhase) + kStateOffset, sizeof block);
    return StateAt(block);
}

const BroadPhaseState& StateOf(const b2BroadPhase& broadPhase)
{
    void* block;
    std::memcpy(&block, reinterpret_cast<const unsigned char*>(&broadPhase) + kStateOffset, sizeof block);
    return StateAt(block);
}

} // namespace detail

// The b2BroadPhase-level API of <quadphase/box2d.h> lives beside the constructor's state, in the object every
// program that creates a broadphase links, so that a statically linked game carries it (and a probe for it finds it).
void SetValidation(b2BroadPhase& broadPhase, bool enabled)
{
    detail::StateOf(broadPhase).SetValidation(enabled);
}

bool IsValidating(const b2BroadPhase& broadPhase)
{
    return detail::StateOf(broadPhase).validation != nullptr;
}

ValidationReport GetValidationReport(const b2BroadPhase& broadPhase)
{
    const detail::BroadPhaseState& state = detail::StateOf(broadPhase);
    return state.validation != nullptr ? detail::ValidationReportOf(*state.validation) : ValidationReport{};
}

} // namespace quadphase
