// SPDX-License-Identifier: MIT
// shooter: a top-down shooter: a player circling the arena fires streams of bullets into a crowd of enemies
// that chase it.
//
// No gravity. A square arena of half side H = max(30, ceil(sqrt(3 N))) m closed by four static walls, with
// N / 20 static crates (half extents 0.5-2 m, random angle) as cover. The player is a kinematic circle
// (radius 1 m) on a circle of radius 0.4 H around the centre, one lap per 21 s. Enemies (N of them): dynamic
// circles of radius 0.5 m (fixed rotation, density 1, friction 0.3) placed in distinct random cells of a 2 m
// grid. Every step each enemy steers towards the player: its velocity moves 10% of the way to the player
// direction times its own speed (2.5-4 m/s). Every step the player fires k = max(2, N / 80) bullets
// (bullet = true: continuous collision against everything; circles of radius 0.1 m, density 0.5) at 35 m/s
// in a spiral of directions; a bullet is destroyed 45 steps (0.75 s) after it was fired. Collision filtering
// as in a game: bullets hit enemies, crates and walls, not each other nor the player. N = 400: H = 35 m, 20
// crates, k = 5, 225 bullets alive.
#include "scene_common.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <vector>

namespace quadphase::scenes::detail
{

namespace
{
constexpr uint16 kWallBit = 0x0001;
constexpr uint16 kEnemyBit = 0x0002;
constexpr uint16 kBulletBit = 0x0004;
constexpr uint16 kPlayerBit = 0x0008;
constexpr int kBulletLifetime = 45;
constexpr float kBulletSpeed = 35.0f;
constexpr float kLapSeconds = 21.0f;

struct Shooter
{
    Rng rng{0};
    float orbit = 10.0f;
    float timeStep = 1.0f / 60.0f;
    b2Body* player = nullptr;
    std::vector<b2Body*> enemies;
    std::vector<float> enemySpeed;
    std::deque<std::pair<b2Body*, int>> bullets; // (body, step fired), oldest first
    int perStep = 2;

    b2Vec2 PlayerTarget(int step) const
    {
        const float angle = 2.0f * b2_pi * static_cast<float>(step) * timeStep / kLapSeconds;
        return b2Vec2(orbit * std::cos(angle), orbit * std::sin(angle));
    }

    void Step(b2World& world, int step)
    {
        // The player follows its circle exactly: velocity = (next target - position) / dt.
        const b2Vec2 playerPosition = player->GetPosition();
        player->SetLinearVelocity((1.0f / timeStep) * (PlayerTarget(step + 2) - playerPosition));

        for (size_t i = 0; i < enemies.size(); ++i)
        {
            b2Body* enemy = enemies[i];
            b2Vec2 toPlayer = playerPosition - enemy->GetPosition();
            toPlayer.Normalize();
            const b2Vec2 velocity = enemy->GetLinearVelocity();
            enemy->SetLinearVelocity(velocity + 0.1f * (enemySpeed[i] * toPlayer - velocity));
        }

        while (!bullets.empty() && step - bullets.front().second >= kBulletLifetime)
        {
            world.DestroyBody(bullets.front().first);
            bullets.pop_front();
        }
        for (int k = 0; k < perStep; ++k)
        {
            const float jitter = rng.Uniform(-0.05f, 0.05f);
            const float angle = 0.37f * static_cast<float>(step) +
                                2.0f * b2_pi * static_cast<float>(k) / static_cast<float>(perStep) + jitter;
            const b2Vec2 direction(std::cos(angle), std::sin(angle));
            b2BodyDef bd;
            bd.type = b2_dynamicBody;
            bd.bullet = true;
            bd.position = playerPosition + 1.3f * direction;
            bd.linearVelocity = kBulletSpeed * direction;
            b2Body* bullet = world.CreateBody(&bd);
            b2FixtureDef fd;
            fd.density = 0.5f;
            fd.filter.categoryBits = kBulletBit;
            fd.filter.maskBits = kWallBit | kEnemyBit;
            AddCircleFixture(bullet, 0.1f, fd);
            bullets.emplace_back(bullet, step);
        }
    }
};
} // namespace

Scene BuildShooter(int size, uint32_t seed)
{
    Scene scene = MakeScene(SceneId::Shooter, size, seed, b2Vec2(0.0f, 0.0f));
    b2World& world = *scene.world;
    Rng rng(seed);

    const float half = std::max(30.0f, std::ceil(std::sqrt(3.0f * static_cast<float>(size))));
    {
        b2Body* walls = CreateStaticBody(world);
        const float t = 1.0f;
        AddBoxFixture(walls, half + 2.0f * t, t, b2Vec2(0.0f, -half - t), 0.0f, 0.3f);
        AddBoxFixture(walls, half + 2.0f * t, t, b2Vec2(0.0f, half + t), 0.0f, 0.3f);
        AddBoxFixture(walls, t, half, b2Vec2(-half - t, 0.0f), 0.0f, 0.3f);
        AddBoxFixture(walls, t, half, b2Vec2(half + t, 0.0f), 0.0f, 0.3f);
    }

    // Distinct random cells of a 2 m grid for crates and enemies: nothing overlaps at start. The grid has
    // (H - 1)^2 cells, more than N + N / 20; crates keep 6 m away from the ring the player drives on.
    const float pitch = 2.0f;
    const int columns = static_cast<int>((2.0f * half - 2.0f) / pitch);
    std::vector<int32_t> cells(static_cast<size_t>(columns) * static_cast<size_t>(columns));
    for (size_t i = 0; i < cells.size(); ++i)
    {
        cells[i] = static_cast<int32_t>(i);
    }
    rng.Shuffle(cells);
    size_t nextCell = 0;
    auto cellCenter = [&](int32_t cell) {
        const int row = cell / columns;
        const int column = cell % columns;
        return b2Vec2(-half + 1.0f + pitch * (static_cast<float>(column) + 0.5f),
                      -half + 1.0f + pitch * (static_cast<float>(row) + 0.5f));
    };

    Shooter shooter;
    shooter.orbit = 0.4f * half;
    shooter.timeStep = scene.timeStep;

    const int crates = size / 20;
    for (int placed = 0; placed < crates && nextCell < cells.size(); ++nextCell)
    {
        const b2Vec2 p = cellCenter(cells[nextCell]);
        if (std::fabs(p.Length() - shooter.orbit) < 6.0f)
        {
            continue;
        }
        b2BodyDef bd;
        bd.type = b2_staticBody;
        bd.position = p;
        bd.angle = rng.Uniform(-b2_pi, b2_pi);
        b2Body* crate = world.CreateBody(&bd);
        const float hx = rng.Uniform(0.5f, 2.0f);
        const float hy = rng.Uniform(0.5f, 2.0f);
        AddBoxFixture(crate, hx, hy, b2Vec2(0.0f, 0.0f), 0.0f, 0.3f);
        ++placed;
    }

    {
        b2BodyDef bd;
        bd.type = b2_kinematicBody;
        bd.position = shooter.PlayerTarget(1);
        shooter.player = world.CreateBody(&bd);
        b2FixtureDef fd;
        fd.filter.categoryBits = kPlayerBit;
        fd.filter.maskBits = kWallBit | kEnemyBit;
        AddCircleFixture(shooter.player, 1.0f, fd);
    }

    for (int i = 0; i < size; ++i)
    {
        b2BodyDef bd;
        bd.type = b2_dynamicBody;
        bd.fixedRotation = true;
        // Cells run out only for tiny arenas; then enemies share cells and Box2D pushes them apart.
        bd.position = cellCenter(cells[(nextCell + static_cast<size_t>(i)) % cells.size()]);
        b2Body* enemy = world.CreateBody(&bd);
        b2FixtureDef fd;
        fd.density = 1.0f;
        fd.friction = 0.3f;
        fd.filter.categoryBits = kEnemyBit;
        AddCircleFixture(enemy, 0.5f, fd);
        shooter.enemies.push_back(enemy);
        shooter.enemySpeed.push_back(rng.Uniform(2.5f, 4.0f));
    }

    shooter.rng = Rng(seed ^ 0x9e3779b9u);
    shooter.perStep = std::max(2, size / 80);
    scene.perStep = [shooter](b2World& w, int step) mutable {
        shooter.Step(w, step);
    };
    return scene;
}

} // namespace quadphase::scenes::detail
