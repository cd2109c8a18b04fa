// SPDX-License-Identifier: MIT
// sparse: an open-world game map: many moving bodies and static rocks spread thinly over a large area.
//
// No gravity. The world is a square of cols x cols cells of 20 m (cols = ceil(sqrt(1.1 N))), closed by four
// static walls. N cells picked at random hold a moving body (half circles of radius 0.5-1 m, half boxes of
// half extents 0.4-1 m; density 1, friction 0.2, restitution 1) with a random direction, a speed of 2-10 m/s
// and a spin of -1..1 rad/s; N / 10 other cells hold a static rock (a box of half extents 1-3 m at a random
// angle, each its own static body). Objects sit at a random point of their cell at least 3.5 m from its
// edges, so nothing touches at start and contacts stay rare (about one body per 400 m^2). N = 4000: 67 x 67
// cells, 1340 m across.
#include "scene_common.h"

#include <cmath>
#include <vector>

namespace quadphase::scenes::detail
{

Scene BuildSparse(int size, uint32_t seed)
{
    Scene scene = MakeScene(SceneId::Sparse, size, seed, b2Vec2(0.0f, 0.0f));
    b2World& world = *scene.world;
    Rng rng(seed);

    const int rocks = size / 10;
    const int columns = static_cast<int>(std::ceil(std::sqrt(1.1 * static_cast<double>(size))));
    const float pitch = 20.0f;
    const float side = pitch * static_cast<float>(columns);
    const float half = 0.5f * side;
    {
        b2Body* walls = CreateStaticBody(world);
        const float t = 1.0f;
        AddBoxFixture(walls, half + 2.0f * t, t, b2Vec2(0.0f, -half - t), 0.0f, 0.2f, 1.0f);
        AddBoxFixture(walls, half + 2.0f * t, t, b2Vec2(0.0f, half + t), 0.0f, 0.2f, 1.0f);
        AddBoxFixture(walls, t, half, b2Vec2(-half - t, 0.0f), 0.0f, 0.2f, 1.0f);
        AddBoxFixture(walls, t, half, b2Vec2(half + t, 0.0f), 0.0f, 0.2f, 1.0f);
    }

    std::vector<int32_t> cells(static_cast<size_t>(columns) * static_cast<size_t>(columns));
    for (size_t i = 0; i < cells.size(); ++i)
    {
        cells[i] = static_cast<int32_t>(i);
    }
    rng.Shuffle(cells);

    const float jitter = 0.5f * pitch - 3.5f;
    auto cellCenter = [&](int32_t cell) {
        const int row = cell / columns;
        const int column = cell % columns;
        // One draw per statement: the evaluation order of function arguments is unspecified.
        const float dx = rng.Uniform(-jitter, jitter);
        const float dy = rng.Uniform(-jitter, jitter);
        return b2Vec2(-half + pitch * (static_cast<float>(column) + 0.5f) + dx,
                      -half + pitch * (static_cast<float>(row) + 0.5f) + dy);
    };

    for (int i = 0; i < size; ++i)
    {
        b2BodyDef bd;
        bd.type = b2_dynamicBody;
        bd.position = cellCenter(cells[static_cast<size_t>(i)]);
        bd.angle = rng.Uniform(-b2_pi, b2_pi);
        const float direction = rng.Uniform(-b2_pi, b2_pi);
        const float speed = rng.Uniform(2.0f, 10.0f);
        bd.linearVelocity.Set(speed * std::cos(direction), speed * std::sin(direction));
        bd.angularVelocity = rng.Uniform(-1.0f, 1.0f);
        b2Body* body = world.CreateBody(&bd);

        b2FixtureDef fd = Material(1.0f, 0.2f, 1.0f);
        AddRandomCircleOrBox(body, fd, rng, 0.5f, 1.0f, 0.4f, 1.0f);
    }

    for (int i = 0; i < rocks; ++i)
    {
        b2BodyDef bd;
        bd.type = b2_staticBody;
        bd.position = cellCenter(cells[static_cast<size_t>(size + i)]);
        bd.angle = rng.Uniform(-b2_pi, b2_pi);
        b2Body* rock = world.CreateBody(&bd);
        const float hx = rng.Uniform(1.0f, 3.0f);
        const float hy = rng.Uniform(1.0f, 3.0f);
        AddBoxFixture(rock, hx, hy, b2Vec2(0.0f, 0.0f), 0.0f, 0.2f, 1.0f);
    }
    return scene;
}

} // namespace quadphase::scenes::detail
