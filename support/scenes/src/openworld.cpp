// SPDX-License-Identifier: MIT
// openworld: an open-world map far from the origin: towns of static buildings with vehicles driving through
// their streets and out into the countryside, trees scattered in between.
//
// No gravity (top-down). The map is centred at (42000, 27000) m, about 50 km from the origin, where a float
// step is 4 mm: positions there keep only about 3 decimal digits below the metre, as in a game that does not
// re-centre its world. T = ceil(N / 250) towns sit on a square grid with a 400 m pitch; each town is 5 x 5
// static buildings (boxes of 10 x 10 m, each its own body) on an 18 m pitch, so streets are 8 m wide.
// Vehicles (N of them, spread evenly over the towns): boxes of 1.8 x 0.9 m (density 1, friction 0.3,
// restitution 0.3, linear damping 0.05, angular damping 0.5) placed along the streets, driving along them at
// 6-16 m/s in either direction; they bounce off buildings and each other and coast up to ~300 m out of town.
// N / 4 trees (static circles of radius 0.5-1.5 m) are scattered over the whole map. Nothing closes the map.
// N = 2000: 8 towns (3 x 3 grid), 500 trees, a map 1.2 km across.
#include "scene_common.h"

#include <cmath>

namespace quadphase::scenes::detail
{

Scene BuildOpenWorld(int size, uint32_t seed)
{
    Scene scene = MakeScene(SceneId::OpenWorld, size, seed, b2Vec2(0.0f, 0.0f));
    b2World& world = *scene.world;
    Rng rng(seed);

    const b2Vec2 center(42000.0f, 27000.0f);
    const int towns = (size + 249) / 250;
    const int townColumns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(towns))));
    const float townPitch = 400.0f;
    const float mapHalf = 0.5f * townPitch * static_cast<float>(townColumns);
    const int blocks = 5;
    const float blockPitch = 18.0f;
    const float buildingHalf = 5.0f;
    const float townHalf = 0.5f * blockPitch * static_cast<float>(blocks); // streets included

    auto townCenter = [&](int town) {
        const int row = town / townColumns;
        const int column = town % townColumns;
        return center + b2Vec2(-mapHalf + townPitch * (static_cast<float>(column) + 0.5f),
                               -mapHalf + townPitch * (static_cast<float>(row) + 0.5f));
    };

    for (int town = 0; town < towns; ++town)
    {
        const b2Vec2 origin = townCenter(town);
        for (int by = 0; by < blocks; ++by)
        {
            for (int bx = 0; bx < blocks; ++bx)
            {
                const b2Vec2 p = origin + b2Vec2(-townHalf + blockPitch * (static_cast<float>(bx) + 0.5f),
                                                 -townHalf + blockPitch * (static_cast<float>(by) + 0.5f));
                b2Body* building = CreateStaticBody(world, p);
                AddBoxFixture(building, buildingHalf, buildingHalf, b2Vec2(0.0f, 0.0f), 0.0f, 0.3f);
            }
        }
    }

    // Vehicles: on the street lines between and around the blocks (6 lines each way), spaced along them.
    for (int i = 0; i < size; ++i)
    {
        const b2Vec2 origin = townCenter(i % towns);
        const bool horizontal = rng.Uniform01() < 0.5f;
        const int line = static_cast<int>(rng.Index(static_cast<uint32_t>(blocks + 1)));
        const float across = -townHalf + blockPitch * static_cast<float>(line);
        const float lane = rng.Uniform(-2.0f, 2.0f);
        const float along = rng.Uniform(-townHalf - 20.0f, townHalf + 20.0f);
        const float speed = rng.Uniform(6.0f, 16.0f) * (rng.Uniform01() < 0.5f ? -1.0f : 1.0f);

        b2BodyDef bd;
        bd.type = b2_dynamicBody;
        bd.linearDamping = 0.05f;
        bd.angularDamping = 0.5f;
        if (horizontal)
        {
            bd.position = origin + b2Vec2(along, across + lane);
            bd.angle = 0.0f;
            bd.linearVelocity.Set(speed, 0.0f);
        }
        else
        {
            bd.position = origin + b2Vec2(across + lane, along);
            bd.angle = 0.5f * b2_pi;
            bd.linearVelocity.Set(0.0f, speed);
        }
        b2Body* vehicle = world.CreateBody(&bd);
        AddBoxFixture(vehicle, 0.9f, 0.45f, b2Vec2(0.0f, 0.0f), 1.0f, 0.3f, 0.3f);
    }

    // Trees: anywhere on the map outside the towns.
    for (int i = 0, placed = 0; placed < size / 4 && i < 100 * size; ++i)
    {
        const float x = rng.Uniform(-mapHalf, mapHalf);
        const float y = rng.Uniform(-mapHalf, mapHalf);
        const float radius = rng.Uniform(0.5f, 1.5f);
        const float townX = std::fmod(x + mapHalf, townPitch) - 0.5f * townPitch;
        const float townY = std::fmod(y + mapHalf, townPitch) - 0.5f * townPitch;
        if (std::fabs(townX) < townHalf + 25.0f && std::fabs(townY) < townHalf + 25.0f)
        {
            continue;
        }
        b2Body* tree = CreateStaticBody(world, center + b2Vec2(x, y));
        AddCircleFixture(tree, radius, b2FixtureDef());
        ++placed;
    }
    return scene;
}

} // namespace quadphase::scenes::detail
