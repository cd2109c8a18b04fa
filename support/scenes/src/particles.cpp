// SPDX-License-Identifier: MIT
// particles: the broadphase paper's test scene.
//
// N circles of radius 0.5 m (density 1, friction 0, restitution 1) with random directions and speeds uniform
// in 1-5 m/s, in a closed square box without gravity. Box side L = sqrt(N pi 0.25 / 0.15), so the circles
// cover 15% of the box. The four walls are static 1 m thick boxes (friction 0, restitution 1) just outside
// the box. Start positions: the box is divided into a grid of ceil(sqrt(N)) columns and ceil(N / columns)
// rows (cells at least 1.6 m wide and tall for every N >= 2), N cells are picked at random and each circle
// is placed at a random point of its cell at least 0.5 m from the cell's edges, so no two circles overlap at
// start. Nothing sleeps (allowSleep off).
#include "scene_common.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace quadphase::scenes::detail
{

Scene BuildParticles(int size, uint32_t seed)
{
    Scene scene = MakeScene(SceneId::Particles, size, seed, b2Vec2(0.0f, 0.0f));
    b2World& world = *scene.world;
    Rng rng(seed);

    const double pi = 3.14159265358979323846;
    const float side = static_cast<float>(std::sqrt(static_cast<double>(size) * pi * 0.25 / 0.15));
    const float half = 0.5f * side;
    {
        b2Body* walls = CreateStaticBody(world);
        const float t = 0.5f; // wall half thickness
        AddBoxFixture(walls, half + 2.0f * t, t, b2Vec2(0.0f, -half - t), 0.0f, 0.0f, 1.0f);
        AddBoxFixture(walls, half + 2.0f * t, t, b2Vec2(0.0f, half + t), 0.0f, 0.0f, 1.0f);
        AddBoxFixture(walls, t, half, b2Vec2(-half - t, 0.0f), 0.0f, 0.0f, 1.0f);
        AddBoxFixture(walls, t, half, b2Vec2(half + t, 0.0f), 0.0f, 0.0f, 1.0f);
    }

    const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(size))));
    const int rows = (size + columns - 1) / columns;
    const float pitch = side / static_cast<float>(columns);
    std::vector<int32_t> cells(static_cast<size_t>(columns) * static_cast<size_t>(rows));
    for (size_t i = 0; i < cells.size(); ++i)
    {
        cells[i] = static_cast<int32_t>(i);
    }
    rng.Shuffle(cells);
    cells.resize(static_cast<size_t>(size));
    std::sort(cells.begin(), cells.end());

    const float radius = 0.5f;
    const float jitter = std::max(0.0f, 0.5f * pitch - radius - 0.01f);
    // Rows fewer than columns leave a strip at the top; spread the rows over the whole height.
    const float rowPitch = side / static_cast<float>(rows);
    const float rowJitter = std::max(0.0f, 0.5f * rowPitch - radius - 0.01f);

    const b2FixtureDef fd = Material(1.0f, 0.0f, 1.0f);

    for (int32_t cell : cells)
    {
        const int row = cell / columns;
        const int column = cell % columns;
        b2BodyDef bd;
        bd.type = b2_dynamicBody;
        bd.allowSleep = false;
        // One draw per statement: the evaluation order of function arguments is unspecified.
        const float dx = rng.Uniform(-jitter, jitter);
        const float dy = rng.Uniform(-rowJitter, rowJitter);
        bd.position.Set(-half + pitch * (static_cast<float>(column) + 0.5f) + dx,
                        -half + rowPitch * (static_cast<float>(row) + 0.5f) + dy);
        const float angle = rng.Uniform(-b2_pi, b2_pi);
        const float speed = rng.Uniform(1.0f, 5.0f);
        bd.linearVelocity.Set(speed * std::cos(angle), speed * std::sin(angle));
        b2Body* body = world.CreateBody(&bd);
        AddCircleFixture(body, radius, fd);
    }
    return scene;
}

} // namespace quadphase::scenes::detail
