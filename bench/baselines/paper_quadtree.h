// SPDX-License-Identifier: MIT
// Benchmark baseline: the design of the paper quadphase comes from (Lok Man Chu, "N-CS159: Parallel Collision
// Detection", SJSU; /work/shared/reference/parallel-collision-detection-paper.md), reproduced as faithfully as the
// BroadPhaseInterface allows so that the same traces can be replayed through it. It is APPROXIMATE by design: it
// misses some overlapping pairs and reports some pairs twice. Every choice is listed in bench/baselines/README.md.
//
// In short:
// - a static quadtree of `levels` levels (the paper's "Lvl"; the root is level 1, so the leaves form a
//   2^(levels-1) x 2^(levels-1) grid) over fixed bounds, built once as nodes with child vectors; its leaves are
//   collected in creation order and re-indexed in row-major order (the paper's linearize step, Figure 2);
// - each FindPairs inserts every live proxy by the centre of its fat box into the one leaf containing it
//   (descending from the root, so centres outside the bounds land in border leaves), then tests, for every leaf,
//   the pairs inside the leaf and, for each object whose fat box crosses one of its leaf's four sides, that object
//   against every object of the edge neighbour on that side (no diagonal neighbours); then clears the tree;
// - the loop over leaves is an OpenMP loop with a settable schedule, and every pair is pushed into ONE shared
//   vector (the caller's `out`) under ONE omp_lock_t, as in the paper.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "brute_force_broad_phase.h"
#include "quadphase/config.h"

namespace quadphase
{
namespace bench
{

/// Which of the pairs found FindPairs reports.
enum class PaperPairReport
{
    /// Every pair the paper's algorithm finds among ALL live proxies (the paper has no move buffer: it recomputes
    /// all pairs every frame). The move buffer is still cleared.
    All,
    /// Only the found pairs with at least one buffered proxy: the pair set of the exact broadphases, minus what the
    /// paper's algorithm misses, plus its duplicates.
    Buffered,
};

/// The paper's static quadtree behind quadphase's BroadPhaseInterface.
///
/// Not exact: a pair is missed when its two fat boxes overlap but the centres lie in leaves that are neither equal
/// nor edge neighbours (diagonal neighbours, objects larger than a leaf), or when they only touch exactly on a leaf
/// side; a pair is reported twice when both fat boxes cross the side between their two leaves. Pair order depends
/// on thread timing (one shared vector under one lock), so it is not deterministic; the multiset of pairs is.
/// Fat boxes, ids, Query, RayCast and GetFatBox are BruteForceBroadPhase's own (it derives from it; Query and
/// RayCast are brute force over the pool): only FindPairs and ShiftOrigin are the paper's.
class PaperQuadtreeBroadPhase final : public BruteForceBroadPhase
{
public:
    static constexpr int kMinLevels = 1; ///< one leaf: the root
    /// 256 x 256 leaves, the paper's largest (its linearize uses bitset<8>)
    static constexpr int kMaxLevels = 9;

    /// The level count for leaves at least `leaf` wide in a square of side `side`: the most levels, up to
    /// kMaxLevels, that keep them so; 1 when none does (qp-replay's and qp-circles' automatic levels).
    static int LevelsFor(double side, double leaf)
    {
        int levels = 1;
        while (levels < kMaxLevels && side / double(1 << levels) >= leaf)
        {
            ++levels;
        }
        return levels;
    }

    /// `levels` is clamped to [kMinLevels, kMaxLevels]. `bounds` is the fixed region (the paper used the window);
    /// an empty, inverted or non-finite region is reported (ErrorCode::InvertedBox / NonFiniteBox) and replaced by
    /// Config's default bounds. `threads`: 0 = OpenMP's own setting, 1 = the paper's sequential quadtree (an
    /// inactive parallel region, no pair lock), n >= 2 = a team of n. `schedule` is the leaf loop's OpenMP schedule
    /// (Static, Dynamic, Guided as compared in the paper; Auto is not from the paper), with OpenMP's default chunk.
    PaperQuadtreeBroadPhase(int levels, const Box& bounds, int threads = 0,
                            Schedule schedule = Schedule::Static,
                            PaperPairReport report = PaperPairReport::All,
                            const FatPolicy& policy = FatPolicy{});
    ~PaperQuadtreeBroadPhase() override;

    PaperQuadtreeBroadPhase(const PaperQuadtreeBroadPhase&) = delete;
    PaperQuadtreeBroadPhase& operator=(const PaperQuadtreeBroadPhase&) = delete;

    /// Inserts every live proxy, finds pairs leaf by leaf, clears the tree; appends to `out` (see PaperPairReport)
    /// and clears the move buffer. Pairs are {a, b} with a < b; a pair may appear twice; some pairs are missed.
    void FindPairs(std::vector<Pair>& out) override;

    /// Moves every stored box and the bounds (the tree's node boxes) by -newOrigin, so that each proxy keeps its
    /// leaf.
    void ShiftOrigin(Vec2 newOrigin) override;

    int GetLevels() const { return m_levels; }

private:
    struct Node
    {
        Box box;
        // indices into m_nodes, in the paper's order TL, TR, BL, BR (see README)
        std::vector<int32_t> children;
        std::vector<ProxyId> objects; // leaves only
        int32_t leafIndex = -1; // row-major index once linearized (the paper's boxIndex); -1 for inner nodes
    };
    struct Locks; // omp_lock_t per leaf and the one pair lock; defined in the .cpp so omp.h stays out of here

    void BuildTree();
    void Generate(int32_t node, int remainingLevels, std::vector<int32_t>& creationOrder);
    void Linearize(const std::vector<int32_t>& creationOrder);
    int32_t Descend(const Box& fat) const;

    PaperPairReport m_report;
    int m_levels;
    int32_t m_leafSide;
    Box m_bounds;
    int m_threads;
    Schedule m_schedule;
    std::vector<Node> m_nodes;     // m_nodes[0] is the root
    std::vector<int32_t> m_leaves; // node index of each leaf, row-major after Linearize (the paper's `leafs`)
    std::unique_ptr<Locks> m_locks;
};

} // namespace bench
} // namespace quadphase
