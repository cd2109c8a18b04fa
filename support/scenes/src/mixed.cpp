// SPDX-License-Identifier: MIT
// mixed: bodies of very different sizes, from pebbles to boulders, falling onto one huge static ground.
//
// Gravity -10. The ground is one static box 20 km wide (its top at y = 0): a single proxy spanning the whole
// world, as a game's terrain collider often does. Above it, N dynamic bodies in three layers, each a grid
// over the same width W = max(40, 1.5 sqrt(N)) m so nothing overlaps at start (density 1, friction 0.6,
// restitution 0.1, shape and size drawn at random):
//   pebbles  (70%): circles of radius 0.05-0.15 m or boxes of half extents 0.05-0.15 m, pitch 0.5 m, y >= 1;
//   crates   (25%): circles of radius 0.3-1 m or boxes of half extents 0.3-0.9 m, pitch 2.5 m, above;
//   boulders  (5%): circles of radius 1.5-3.5 m or boxes of half extents 1.5-3 m, pitch 8 m, on top.
// A few static ledges (N / 100 boxes of 4-60 m x 1 m, tilted up to 0.3 rad, 1-12 m up) stand within 1.5 W
// beside the column. Radii span a factor of 70 among the dynamic bodies and 10^5 with the ground. The
// boulders land on the crates and pebbles and the heap spreads sideways over the ground. N = 3000: W = 82 m.
#include "scene_common.h"

#include <algorithm>
#include <cmath>

namespace quadphase::scenes::detail
{

Scene BuildMixed(int size, uint32_t seed)
{
    Scene scene = MakeScene(SceneId::Mixed, size, seed, b2Vec2(0.0f, -10.0f));
    b2World& world = *scene.world;
    Rng rng(seed);

    {
        b2Body* ground = CreateStaticBody(world);
        AddBoxFixture(ground, 10000.0f, 5.0f, b2Vec2(0.0f, -5.0f), 0.0f);
    }

    const float width = std::max(40.0f, 1.5f * std::sqrt(static_cast<float>(size)));
    const int ledges = size / 100;
    for (int i = 0; i < ledges; ++i)
    {
        const float side = (i % 2 == 0) ? -1.0f : 1.0f;
        const float halfLength = rng.Uniform(2.0f, 30.0f);
        const float x = side * (0.5f * width + 10.0f + rng.Uniform(0.0f, 1.5f * width));
        const float y = rng.Uniform(1.0f, 12.0f);
        const float angle = rng.Uniform(-0.3f, 0.3f);
        b2Body* ledge = CreateStaticBody(world, b2Vec2(x, y));
        AddBoxFixture(ledge, halfLength, 0.5f, b2Vec2(0.0f, 0.0f), 0.0f, 0.6f, 0.0f, angle);
    }

    const int boulders = size / 20;
    const int crates = size / 4;
    const int pebbles = size - boulders - crates;

    struct Layer
    {
        int count;
        float pitch;
        float rMin, rMax, hMin, hMax;
    };
    const Layer layers[] = {
        {pebbles, 0.5f, 0.05f, 0.15f, 0.05f, 0.15f},
        {crates, 2.5f, 0.3f, 1.0f, 0.3f, 0.9f},
        {boulders, 8.0f, 1.5f, 3.5f, 1.5f, 3.0f},
    };
    float bottom = 1.0f;
    for (const Layer& layer : layers)
    {
        const int columns = std::max(1, static_cast<int>(width / layer.pitch));
        const float x0 = -0.5f * layer.pitch * static_cast<float>(columns - 1);
        const float y0 = bottom + 0.5f * layer.pitch;
        for (int i = 0; i < layer.count; ++i)
        {
            const int row = i / columns;
            const int column = i % columns;
            b2BodyDef bd;
            bd.type = b2_dynamicBody;
            bd.position.Set(x0 + layer.pitch * static_cast<float>(column),
                            y0 + layer.pitch * static_cast<float>(row));
            bd.angle = rng.Uniform(-b2_pi, b2_pi);
            b2Body* body = world.CreateBody(&bd);
            b2FixtureDef fd = Material(1.0f, 0.6f, 0.1f);
            AddRandomCircleOrBox(body, fd, rng, layer.rMin, layer.rMax, layer.hMin, layer.hMax);
        }
        const int rows = (layer.count + columns - 1) / columns;
        bottom += layer.pitch * static_cast<float>(rows);
    }
    return scene;
}

} // namespace quadphase::scenes::detail
