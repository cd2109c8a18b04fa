// SPDX-License-Identifier: MIT
// Scenes are deterministic functions of (size, seed); the registry and the random mapping behave.
#include <catch2/catch.hpp>

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "quadphase_scenes/scenes.h"

namespace
{

using quadphase::scenes::Scene;
using quadphase::scenes::SceneId;
using quadphase::scenes::SceneInfo;

/// A small size of each scene for quick tests.
int SmallSize(const SceneInfo& info)
{
    switch (info.id)
    {
    case SceneId::Pyramid:
        return 12;
    case SceneId::Rain:
        return 500;
    case SceneId::Tumbler:
        return 200;
    case SceneId::Tiles:
        return 400;
    case SceneId::Particles:
        return 500;
    case SceneId::Bullets:
        return 120;
    case SceneId::Sparse:
        return 300;
    case SceneId::Shooter:
        return 100;
    case SceneId::OpenWorld:
        return 300;
    case SceneId::Mixed:
        return 300;
    case SceneId::Terrain:
        return 150;
    case SceneId::Churn:
        return 200;
    }
    return info.minSize;
}

std::vector<uint32_t> Run(SceneId id, int size, uint32_t seed, int steps)
{
    Scene scene = quadphase::scenes::BuildScene(id, size, seed);
    for (int i = 0; i < steps; ++i)
    {
        quadphase::scenes::StepScene(scene);
    }
    REQUIRE(scene.stepCount == steps);
    return quadphase::scenes::BodyStateBits(*scene.world);
}

} // namespace

TEST_CASE("each scene is deterministic: same size and seed, same bits after 60 steps",
          "[scenes][determinism]")
{
    for (const SceneInfo& info : quadphase::scenes::AllScenes())
    {
        const int size = SmallSize(info);
        INFO("scene " << info.name << " size " << size);
        const std::vector<uint32_t> first = Run(info.id, size, 42, 60);
        const std::vector<uint32_t> second = Run(info.id, size, 42, 60);
        REQUIRE(!first.empty());
        CHECK(first == second);
    }
}

TEST_CASE("randomised scenes depend on the seed", "[scenes][determinism]")
{
    for (SceneId id : {SceneId::Rain, SceneId::Particles, SceneId::Bullets, SceneId::Sparse})
    {
        const SceneInfo& info = quadphase::scenes::GetSceneInfo(id);
        INFO("scene " << info.name);
        const int steps = id == SceneId::Bullets ? 30 : 1;
        CHECK(Run(id, SmallSize(info), 1, steps) != Run(id, SmallSize(info), 2, steps));
    }
}

TEST_CASE("scene sizes and body counts", "[scenes]")
{
    using quadphase::scenes::BuildScene;
    using quadphase::scenes::CountBodies;
    using quadphase::scenes::CountFixtures;

    // pyramid: ground + base (base + 1) / 2 boxes
    CHECK(CountBodies(*BuildScene(SceneId::Pyramid, 20, 0).world) == 1 + 210);
    // tiles: default 200 x 20 tiles on one static body + a 20-box-base pyramid
    {
        Scene tiles = BuildScene(SceneId::Tiles, 4000, 0);
        CHECK(CountBodies(*tiles.world) == 1 + 210);
        CHECK(CountFixtures(*tiles.world) == 4000 + 210);
    }
    // rain: container + N bodies
    CHECK(CountBodies(*BuildScene(SceneId::Rain, 1000, 3).world) == 1 + 1000);
    // particles: walls + N circles
    CHECK(CountBodies(*BuildScene(SceneId::Particles, 1000, 3).world) == 1 + 1000);
    // sparse: walls + N moving bodies + N / 10 rocks
    CHECK(CountBodies(*BuildScene(SceneId::Sparse, 1000, 3).world) == 1 + 1000 + 100);
    // tumbler: boxes are spawned over the first 200 steps
    {
        Scene tumbler = BuildScene(SceneId::Tumbler, 800, 0);
        CHECK(CountBodies(*tumbler.world) == 2);
        for (int i = 0; i < 200; ++i)
        {
            quadphase::scenes::StepScene(tumbler);
        }
        CHECK(CountBodies(*tumbler.world) == 2 + 800);
        quadphase::scenes::StepScene(tumbler);
        CHECK(CountBodies(*tumbler.world) == 2 + 800);
    }
    // bullets: arena + pyramid of 136; every bullet fired once in the first 120 steps
    {
        Scene bullets = BuildScene(SceneId::Bullets, 240, 0);
        CHECK(CountBodies(*bullets.world) == 1 + 136);
        for (int i = 0; i < 120; ++i)
        {
            quadphase::scenes::StepScene(bullets);
        }
        CHECK(CountBodies(*bullets.world) == 1 + 136 + 240);
    }
}

TEST_CASE("game scenes: body counts, churn every step, a map far from the origin", "[scenes]")
{
    using quadphase::scenes::BuildScene;
    using quadphase::scenes::CountBodies;
    using quadphase::scenes::StepScene;

    // churn: N bodies + the container at every step; every step creates new bodies (tagged by user data,
    // since Box2D reuses a destroyed body's memory) and destroys as many.
    {
        Scene churn = BuildScene(SceneId::Churn, 240, 5);
        REQUIRE(CountBodies(*churn.world) == 1 + 240);
        for (int step = 0; step < 30; ++step)
        {
            for (b2Body* body = churn.world->GetBodyList(); body != nullptr; body = body->GetNext())
            {
                body->GetUserData().pointer = 1;
            }
            StepScene(churn);
            int created = 0;
            for (b2Body* body = churn.world->GetBodyList(); body != nullptr; body = body->GetNext())
            {
                created += body->GetUserData().pointer == 0 ? 1 : 0;
            }
            INFO("step " << step);
            CHECK(created == 2); // max(1, 240 / 120)
            CHECK(CountBodies(*churn.world) == 1 + 240);
        }
    }
    // shooter: walls + N / 20 crates + player + N enemies, then 5 bullets per step (N = 400) alive for 45
    // steps.
    {
        Scene shooter = BuildScene(SceneId::Shooter, 400, 5);
        CHECK(CountBodies(*shooter.world) == 1 + 20 + 1 + 400);
        for (int step = 0; step < 100; ++step)
        {
            StepScene(shooter);
        }
        CHECK(CountBodies(*shooter.world) == 1 + 20 + 1 + 400 + 5 * 45);
    }
    // openworld: ceil(300 / 250) = 2 towns of 5 x 5 buildings, 300 vehicles, 75 trees; every body more than
    // 40 km from the origin on x.
    {
        Scene world = BuildScene(SceneId::OpenWorld, 300, 5);
        CHECK(CountBodies(*world.world) == 2 * 25 + 300 + 75);
        for (const b2Body* body = world.world->GetBodyList(); body != nullptr; body = body->GetNext())
        {
            CHECK(body->GetPosition().x > 40000.0f);
        }
    }
}

TEST_CASE("scene registry: names, parsing and size checks", "[scenes]")
{
    const auto& scenes = quadphase::scenes::AllScenes();
    REQUIRE(scenes.size() == 12);
    for (const SceneInfo& info : scenes)
    {
        INFO("scene " << info.name);
        CHECK(quadphase::scenes::ParseSceneName(info.name) == info.id);
        CHECK(std::string(quadphase::scenes::SceneName(info.id)) == info.name);
        CHECK(info.minSize <= info.defaultSize);
        CHECK(info.defaultSize <= info.maxSize);
        CHECK_THROWS_AS(quadphase::scenes::BuildScene(info.id, info.minSize - 1, 0), std::invalid_argument);
        CHECK_THROWS_AS(quadphase::scenes::BuildScene(info.id, info.maxSize + 1, 0), std::invalid_argument);
    }
    CHECK(quadphase::scenes::ParseSceneName("RAIN") == SceneId::Rain);
    CHECK_FALSE(quadphase::scenes::ParseSceneName("drizzle").has_value());
    CHECK_FALSE(quadphase::scenes::ParseSceneName("").has_value());
    CHECK(quadphase::scenes::SceneNameList() ==
          "pyramid, rain, tumbler, tiles, particles, bullets, sparse, shooter, "
          "openworld, mixed, terrain, churn");
}

TEST_CASE("Rng: standard mt19937 stream with portable mappings", "[scenes]")
{
    quadphase::scenes::Rng rng(5489u);   // std::mt19937's default seed
    CHECK(rng.NextU32() == 3499211612u); // first output, fixed by the C++ standard's definition of mt19937
    quadphase::scenes::Rng a(5489u);
    CHECK(a.Uniform01() == static_cast<float>(3499211612u >> 8) / 16777216.0f);

    quadphase::scenes::Rng r(123u);
    for (int i = 0; i < 10000; ++i)
    {
        const float u = r.Uniform01();
        REQUIRE(u >= 0.0f);
        REQUIRE(u < 1.0f);
        const float v = r.Uniform(-2.0f, 3.0f);
        REQUIRE(v >= -2.0f);
        REQUIRE(v < 3.0f);
        REQUIRE(r.Index(7) < 7u);
    }
    std::vector<int32_t> values = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
    r.Shuffle(values);
    std::vector<int32_t> sorted = values;
    std::sort(sorted.begin(), sorted.end());
    CHECK(sorted == std::vector<int32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9});
}
