// SPDX-License-Identifier: MIT
// terrain: a rolling landscape made of one chain shape, with wheels and rocks rolling down into its valleys.
//
// Gravity -10. The ground is one static b2ChainShape with a vertex every metre over a width
// W = max(200, 0.6 N) m, heights the sum of three sines (amplitudes 6, 3 and 0.8 m, wavelengths 97, 31 and
// 7.7 m), closed at both ends by 40 m cliffs; Box2D gives every segment of a chain its own proxy, so the
// ground alone is W static proxies. N dynamic bodies (density 1, friction 0.8, angular damping 0.1): 70%
// circles of radius 0.3-1.2 m, 30% regular polygons of 5-8 sides and radius 0.4-1 m, start on a grid with a
// 2.6 m pitch from 5 m above the highest hill, drop, and roll downhill into the valleys, where they pile up.
// N = 1000: W = 600 m, 5 rows of 229.
#include "scene_common.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace quadphase::scenes::detail
{

namespace
{
float TerrainHeight(float x)
{
    const float twoPi = 2.0f * b2_pi;
    return 6.0f * std::sin(twoPi * x / 97.0f) + 3.0f * std::sin(twoPi * x / 31.0f + 1.0f) +
           0.8f * std::sin(twoPi * x / 7.7f + 2.0f);
}
} // namespace

Scene BuildTerrain(int size, uint32_t seed)
{
    Scene scene = MakeScene(SceneId::Terrain, size, seed, b2Vec2(0.0f, -10.0f));
    b2World& world = *scene.world;
    Rng rng(seed);

    const int segments = std::max(200, (6 * size) / 10);
    const float half = 0.5f * static_cast<float>(segments);
    float highest = 0.0f;
    {
        std::vector<b2Vec2> vertices;
        vertices.reserve(static_cast<size_t>(segments) + 3);
        vertices.emplace_back(-half, TerrainHeight(-half) + 40.0f); // left cliff
        for (int i = 0; i <= segments; ++i)
        {
            const float x = -half + static_cast<float>(i);
            const float y = TerrainHeight(x);
            highest = std::max(highest, y);
            vertices.emplace_back(x, y);
        }
        vertices.emplace_back(half, TerrainHeight(half) + 40.0f); // right cliff
        b2ChainShape chain;
        chain.CreateChain(vertices.data(), static_cast<int32>(vertices.size()),
                          vertices.front() + b2Vec2(0.0f, 1.0f), vertices.back() + b2Vec2(0.0f, 1.0f));
        b2Body* ground = CreateStaticBody(world);
        b2FixtureDef fd;
        fd.shape = &chain;
        fd.friction = 0.8f;
        ground->CreateFixture(&fd);
    }

    const float pitch = 2.6f;
    const SpawnGrid grid{pitch, std::max(1, static_cast<int>((2.0f * half - 4.0f) / pitch)), highest + 5.0f};
    for (int i = 0; i < size; ++i)
    {
        b2BodyDef bd;
        bd.type = b2_dynamicBody;
        bd.angularDamping = 0.1f;
        bd.position = grid.At(i);
        bd.angle = rng.Uniform(-b2_pi, b2_pi);
        b2Body* body = world.CreateBody(&bd);
        b2FixtureDef fd;
        fd.density = 1.0f;
        fd.friction = 0.8f;
        if (rng.Uniform01() < 0.7f)
        {
            AddCircleFixture(body, rng.Uniform(0.3f, 1.2f), fd);
        }
        else
        {
            const int sides = 5 + static_cast<int>(rng.Index(4));
            const float radius = rng.Uniform(0.4f, 1.0f);
            b2Vec2 points[8];
            for (int k = 0; k < sides; ++k)
            {
                const float a = 2.0f * b2_pi * static_cast<float>(k) / static_cast<float>(sides);
                points[k].Set(radius * std::cos(a), radius * std::sin(a));
            }
            b2PolygonShape polygon;
            polygon.Set(points, sides);
            fd.shape = &polygon;
            body->CreateFixture(&fd);
        }
    }
    return scene;
}

} // namespace quadphase::scenes::detail
