// SPDX-License-Identifier: MIT
// rain: a large number of mixed circles and boxes dropped into a wide open-top container.
//
// Bodies: half circles (radius 0.2-0.5 m), half boxes (half extents 0.2-0.45 m, random angle), density 1,
// friction 0.6, restitution 0.1, chosen at random per body. Container: static floor plus two walls
// (one static body, three box fixtures), inner width W = 3 sqrt(N) + 20 m, wall height = 1.3 x the expected
// pile height + 5 m (expected pile = N x 0.75 m^2 / W). Spawn: a grid with 1.5 m pitch (every body fits in a
// 1.3 m circle, plus +-0.1 m jitter: nothing overlaps at start) filling the container's width row by row,
// starting 2 m above the walls' top. Bodies start with a small random velocity
// (-1..1 m/s sideways, -2..0 m/s down) and linear damping 1 ("air drag": terminal velocity 10 m/s).
//
// N = 16000: W = 399 m, walls 45 m, a grid of 265 x 61 cells from y = 47 to 137 m. The bodies fall for the
// first ~5 s (300 steps): every proxy moves every step and neighbours' fattened boxes overlap, a broadphase-
// heavy phase; then the pile forms. Without the drag, bodies hit the floor at 30-50 m/s and Box2D's
// continuous collision (O(contacts) per time-of-impact event, and a settling pile produces hundreds of events
// per step) made steps take seconds; with it, impacts are gentle and the settled pile still costs ~30 ms per
// step of TOI work at 16000 bodies (measured on the development machine).
#include "scene_common.h"

#include <algorithm>
#include <cmath>

namespace quadphase::scenes::detail
{

Scene BuildRain(int size, uint32_t seed)
{
    Scene scene = MakeScene(SceneId::Rain, size, seed, b2Vec2(0.0f, -10.0f));
    b2World& world = *scene.world;
    Rng rng(seed);

    const float n = static_cast<float>(size);
    const float innerWidth = std::floor(3.0f * std::sqrt(n) + 20.0f);
    const float pileHeight = n * 0.75f / innerWidth;
    const float wallHeight = std::ceil(1.3f * pileHeight + 5.0f);
    const float wallHalfThickness = 0.5f;
    {
        b2Body* container = CreateStaticBody(world);
        const float halfWidth = 0.5f * innerWidth;
        // floor: top surface at y = 0
        AddBoxFixture(container, halfWidth + 2.0f * wallHalfThickness, wallHalfThickness,
                      b2Vec2(0.0f, -wallHalfThickness), 0.0f);
        // walls
        for (float side : {-1.0f, 1.0f})
        {
            AddBoxFixture(container, wallHalfThickness, 0.5f * wallHeight,
                          b2Vec2(side * (halfWidth + wallHalfThickness), 0.5f * wallHeight), 0.0f);
        }
    }

    // Spawn grid above the container: cells of 1.5 m, as many columns as fit inside the walls.
    const float pitch = 1.5f;
    const SpawnGrid grid{pitch, std::max(1, static_cast<int>(innerWidth / pitch) - 1), wallHeight + 2.0f};

    for (int i = 0; i < size; ++i)
    {
        b2BodyDef bd;
        bd.type = b2_dynamicBody;
        // One draw per statement: the evaluation order of function arguments is unspecified.
        const float dx = rng.Uniform(-0.1f, 0.1f);
        const float dy = rng.Uniform(-0.1f, 0.1f);
        bd.position = grid.At(i) + b2Vec2(dx, dy);
        bd.linearDamping = 1.0f; // air drag: terminal velocity g / 1 = 10 m/s
        bd.angle = rng.Uniform(-b2_pi, b2_pi);
        const float vx = rng.Uniform(-1.0f, 1.0f);
        const float vy = rng.Uniform(-2.0f, 0.0f);
        bd.linearVelocity.Set(vx, vy);
        b2Body* body = world.CreateBody(&bd);

        b2FixtureDef fd = Material(1.0f, 0.6f, 0.1f);
        AddRandomCircleOrBox(body, fd, rng, 0.2f, 0.5f, 0.2f, 0.45f);
    }
    return scene;
}

} // namespace quadphase::scenes::detail
