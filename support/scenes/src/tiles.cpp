// SPDX-License-Identifier: MIT
// tiles: the Box2D testbed's Tiles benchmark (a static-proxy stress test), with a configurable tile count.
//
// One static body holds rows x columns box fixtures of 1x1 m (each fixture is its own broadphase proxy),
// rows = max(1, round(sqrt(size / 10))), columns = round(size / rows): size 4000 gives 20 rows of 200 tiles
// (the testbed uses 10 rows). The top row's surface is at y = 0. On top sits the testbed's 20-box-base
// pyramid (210 dynamic boxes). The seed is unused.
#include "scene_common.h"

#include <algorithm>
#include <cmath>

namespace quadphase::scenes::detail
{

Scene BuildTiles(int size, uint32_t seed)
{
    Scene scene = MakeScene(SceneId::Tiles, size, seed, b2Vec2(0.0f, -10.0f));
    b2World& world = *scene.world;

    const int rows = std::max(1, static_cast<int>(std::lround(std::sqrt(size / 10.0))));
    const int columns = std::max(1, static_cast<int>(std::lround(static_cast<double>(size) / rows)));

    const float a = 0.5f; // tile half extent
    b2Body* ground = CreateStaticBody(world, b2Vec2(0.0f, -a));
    for (int row = 0; row < rows; ++row)
    {
        const float y = -2.0f * a * static_cast<float>(row);
        for (int column = 0; column < columns; ++column)
        {
            const float x = -a * static_cast<float>(columns) + 2.0f * a * static_cast<float>(column);
            AddBoxFixture(ground, a, a, b2Vec2(x, y), 0.0f, 0.2f);
        }
    }

    AddBoxPyramid(world, 20, -7.0f, 0.75f);
    return scene;
}

} // namespace quadphase::scenes::detail
