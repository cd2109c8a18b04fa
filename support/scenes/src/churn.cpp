// SPDX-License-Identifier: MIT
// churn: create-and-destroy churn, as in games that spawn and despawn debris, pickups and projectiles.
//
// Gravity -10. An open-top container (one static body: floor with its top at y = 0 and two walls) of inner
// width W = 1.2 c + 1 m, c = ceil(sqrt(N)), walls 1.5 W tall. At build time N bodies (half circles of radius
// 0.25-0.5 m, half boxes of half extents 0.25-0.45 m; density 1, friction 0.6, restitution 0.1) fill a grid
// of c columns with a 1.2 m pitch from y = 1 m: about a square pile. Every step, perStep destroys k = max(1,
// N / 120) live bodies picked at random (so a body lives 2 s on average, some much longer) and creates k new
// ones at random points above the walls, falling at 5 m/s: the body count stays N and every step creates and
// destroys proxies. N = 2000: c = 45, W = 55 m, k = 16.
#include "scene_common.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace quadphase::scenes::detail
{

namespace
{
struct Churn
{
    Rng rng{0};
    std::vector<b2Body*> live;
    int perStep = 1;
    float halfWidth = 1.0f;
    float spawnY = 1.0f;

    void Spawn(b2World& world, b2Vec2 position, b2Vec2 velocity)
    {
        b2BodyDef bd;
        bd.type = b2_dynamicBody;
        bd.position = position;
        bd.angle = rng.Uniform(-b2_pi, b2_pi);
        bd.linearVelocity = velocity;
        b2Body* body = world.CreateBody(&bd);
        b2FixtureDef fd = Material(1.0f, 0.6f, 0.1f);
        AddRandomCircleOrBox(body, fd, rng, 0.25f, 0.5f, 0.25f, 0.45f);
        live.push_back(body);
    }

    void Step(b2World& world)
    {
        for (int i = 0; i < perStep && !live.empty(); ++i)
        {
            const size_t victim = rng.Index(static_cast<uint32_t>(live.size()));
            world.DestroyBody(live[victim]);
            live[victim] = live.back();
            live.pop_back();
        }
        for (int i = 0; i < perStep; ++i)
        {
            const float x = rng.Uniform(-halfWidth + 0.6f, halfWidth - 0.6f);
            const float y = rng.Uniform(spawnY, spawnY + 4.0f);
            Spawn(world, b2Vec2(x, y), b2Vec2(0.0f, -5.0f));
        }
    }
};
} // namespace

Scene BuildChurn(int size, uint32_t seed)
{
    Scene scene = MakeScene(SceneId::Churn, size, seed, b2Vec2(0.0f, -10.0f));
    b2World& world = *scene.world;

    const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(size))));
    const float pitch = 1.2f;
    const float innerWidth = pitch * static_cast<float>(columns) + 1.0f;
    const float halfWidth = 0.5f * innerWidth;
    const float wallHeight = 1.5f * innerWidth;
    {
        b2Body* container = CreateStaticBody(world);
        const float t = 0.5f;
        AddBoxFixture(container, halfWidth + 2.0f * t, t, b2Vec2(0.0f, -t), 0.0f);
        for (float side : {-1.0f, 1.0f})
        {
            AddBoxFixture(container, t, 0.5f * wallHeight, b2Vec2(side * (halfWidth + t), 0.5f * wallHeight),
                          0.0f);
        }
    }

    Churn churn;
    churn.rng = Rng(seed);
    churn.perStep = std::max(1, size / 120);
    churn.halfWidth = halfWidth;
    churn.spawnY = wallHeight + 1.0f;
    churn.live.reserve(static_cast<size_t>(size));
    const float x0 = -0.5f * pitch * static_cast<float>(columns - 1);
    for (int i = 0; i < size; ++i)
    {
        const int row = i / columns;
        const int column = i % columns;
        churn.Spawn(world,
                    b2Vec2(x0 + pitch * static_cast<float>(column), 1.0f + pitch * static_cast<float>(row)),
                    b2Vec2(0.0f, 0.0f));
    }
    scene.perStep = [churn](b2World& w, int) mutable {
        churn.Step(w);
    };
    return scene;
}

} // namespace quadphase::scenes::detail
