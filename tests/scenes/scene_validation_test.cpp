// SPDX-License-Identifier: MIT
// Every scene, stepped 600 times with the quadtree broadphase in validation mode: at each UpdatePairs a
// shadow b2DynamicTree (Box2D 2.4.1's own logic) computes the pairs the stock broadphase would report, and
// the fat AABBs and MoveProxy decisions are compared too. Any disagreement is a mismatch.
//
// Sizes are CI-friendly (validation roughly doubles the broadphase cost); the whole file runs in well under
// two minutes on 2 cores at -O2.
#include <catch2/catch.hpp>

#include <set>

#include "quadphase/box2d.h"
#include "quadphase_scenes/scenes.h"

namespace
{

using quadphase::scenes::SceneId;

constexpr int kSteps = 600;
constexpr uint32_t kSeed = 7;

struct ValidationCase
{
    SceneId id;
    int size;
};

// One entry per scene; the test "every scene has a validation case" keeps this list complete.
const ValidationCase kCases[] = {
    {SceneId::Pyramid, 40},     {SceneId::Rain, 4000},   {SceneId::Tumbler, 400}, {SceneId::Tiles, 4000},
    {SceneId::Particles, 4000}, {SceneId::Bullets, 400}, {SceneId::Sparse, 2000}, {SceneId::Shooter, 300},
    {SceneId::OpenWorld, 600},  {SceneId::Mixed, 500},   {SceneId::Terrain, 500}, {SceneId::Churn, 500},
};

int SizeFor(SceneId id)
{
    for (const ValidationCase& c : kCases)
    {
        if (c.id == id)
        {
            return c.size;
        }
    }
    FAIL("no validation size for scene " << quadphase::scenes::SceneName(id));
    return 0;
}

void RunValidated(SceneId id)
{
    const int size = SizeFor(id);
    quadphase::scenes::Scene scene = quadphase::scenes::BuildScene(id, size, kSeed);
    b2World& world = *scene.world;
    quadphase::SetValidation(world, true);

    int64_t contactSteps = 0;
    for (int step = 0; step < kSteps; ++step)
    {
        quadphase::scenes::StepScene(scene);
        if (world.GetContactCount() > 0)
        {
            ++contactSteps;
        }
    }

    const quadphase::ValidationReport report = quadphase::GetValidationReport(world);
    INFO("scene " << quadphase::scenes::SceneName(id) << " size " << size << ": " << report.checks
                  << " checks, " << report.pairsCompared << " pairs compared, " << report.mismatches
                  << " mismatches; first: " << report.firstMismatch);
    REQUIRE(report.mismatches == 0);
    REQUIRE(report.checks > 0);
    REQUIRE(report.pairsCompared > 0);
    // The scene did something a broadphase can get wrong.
    CHECK(contactSteps > 0);
}

} // namespace

TEST_CASE("every scene has a validation case", "[scenes][validation]")
{
    std::set<SceneId> covered;
    for (const ValidationCase& c : kCases)
    {
        covered.insert(c.id);
        const quadphase::scenes::SceneInfo& info = quadphase::scenes::GetSceneInfo(c.id);
        CHECK(c.size >= info.minSize);
        CHECK(c.size <= info.maxSize);
    }
    for (const quadphase::scenes::SceneInfo& info : quadphase::scenes::AllScenes())
    {
        INFO("scene " << info.name);
        CHECK(covered.count(info.id) == 1);
    }
}

TEST_CASE("pyramid validates against the shadow tree", "[scenes][validation]")
{
    RunValidated(SceneId::Pyramid);
}

TEST_CASE("rain validates against the shadow tree", "[scenes][validation]")
{
    RunValidated(SceneId::Rain);
}

TEST_CASE("tumbler validates against the shadow tree", "[scenes][validation]")
{
    RunValidated(SceneId::Tumbler);
}

TEST_CASE("tiles validates against the shadow tree", "[scenes][validation]")
{
    RunValidated(SceneId::Tiles);
}

TEST_CASE("particles validates against the shadow tree", "[scenes][validation]")
{
    RunValidated(SceneId::Particles);
}

TEST_CASE("bullets validates against the shadow tree", "[scenes][validation]")
{
    RunValidated(SceneId::Bullets);
}

TEST_CASE("sparse validates against the shadow tree", "[scenes][validation]")
{
    RunValidated(SceneId::Sparse);
}

TEST_CASE("shooter validates against the shadow tree", "[scenes][validation]")
{
    RunValidated(SceneId::Shooter);
}

TEST_CASE("openworld validates against the shadow tree", "[scenes][validation]")
{
    RunValidated(SceneId::OpenWorld);
}

TEST_CASE("mixed validates against the shadow tree", "[scenes][validation]")
{
    RunValidated(SceneId::Mixed);
}

TEST_CASE("terrain validates against the shadow tree", "[scenes][validation]")
{
    RunValidated(SceneId::Terrain);
}

TEST_CASE("churn validates against the shadow tree", "[scenes][validation]")
{
    RunValidated(SceneId::Churn);
}
