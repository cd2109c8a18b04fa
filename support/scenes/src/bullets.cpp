// SPDX-License-Identifier: MIT
// bullets: a shooting gallery: many fast bullet bodies (continuous collision against everything) fired
// through slotted thin walls at a pile of boxes, so most steps have many time-of-impact events.
//
// Arena (one static body): ground with its top at y = 0 from x = -62 to 62, side walls and a ceiling at
// y = 45, all 1 m thick, so nothing escapes. Thin walls (0.1 m thick, 2 m tall segments separated by 1 m
// slots, up to y = 23) stand at x = +-20 and +-32, the outer ones with their slots shifted by 1.5 m. A
// 16-box-base pyramid (136 unit boxes, density 5) stands at the centre.
//
// Bullets (size of them): alternately circles of radius 0.1 m and boxes of 0.2 x 0.2 m, density 10,
// bullet = true, are fired by perStep, from the side given by their index (even: left, odd: right), from a
// random point of x in +-[44, 58], y in [0.5, 22.5], with horizontal speed 40-80 m/s towards the centre and
// vertical speed -2..6 m/s. Firing is spread evenly over time: floor((step + 1) size / 120) shots by the
// end of step `step`, so every bullet is fired once during the first 120 steps (bodies are created on their
// first shot) and re-fired (teleported back with a new velocity) every 120 steps (2 s) after that. A bullet
// takes 1-2 steps to cross a wall's thickness, ~0.6-1.1 s to cross the arena, and ends up lying on the
// ground.
#include "scene_common.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace quadphase::scenes::detail
{

namespace
{
constexpr int kPeriod = 120;

struct Gun
{
    int size = 0;
    Rng rng{0};
    std::vector<b2Body*> bullets;
    int64_t fired = 0;

    void Fire(b2World& world, int index)
    {
        const float side = (index % 2 == 0) ? -1.0f : 1.0f;
        const float x = side * rng.Uniform(44.0f, 58.0f);
        const float y = rng.Uniform(0.5f, 22.5f);
        const float vx = -side * rng.Uniform(40.0f, 80.0f);
        const float vy = rng.Uniform(-2.0f, 6.0f);

        b2Body*& body = bullets[static_cast<size_t>(index)];
        if (body == nullptr)
        {
            b2BodyDef bd;
            bd.type = b2_dynamicBody;
            bd.bullet = true;
            bd.position.Set(x, y);
            bd.linearVelocity.Set(vx, vy);
            body = world.CreateBody(&bd);

            b2FixtureDef fd = Material(10.0f, 0.4f, 0.2f);
            if (index % 4 < 2)
            {
                AddCircleFixture(body, 0.1f, fd);
            }
            else
            {
                b2PolygonShape box;
                box.SetAsBox(0.1f, 0.1f);
                fd.shape = &box;
                body->CreateFixture(&fd);
            }
        }
        else
        {
            body->SetTransform(b2Vec2(x, y), 0.0f);
            body->SetLinearVelocity(b2Vec2(vx, vy));
            body->SetAngularVelocity(0.0f);
            body->SetAwake(true);
        }
    }

    void Step(b2World& world, int step)
    {
        const int64_t target = (static_cast<int64_t>(step) + 1) * size / kPeriod;
        for (; fired < target; ++fired)
        {
            Fire(world, static_cast<int>(fired % size));
        }
    }
};
} // namespace

Scene BuildBullets(int size, uint32_t seed)
{
    Scene scene = MakeScene(SceneId::Bullets, size, seed, b2Vec2(0.0f, -10.0f));
    b2World& world = *scene.world;

    {
        b2Body* arena = CreateStaticBody(world);
        const float t = 0.5f;
        AddBoxFixture(arena, 62.0f + 2.0f * t, t, b2Vec2(0.0f, -t), 0.0f);        // ground
        AddBoxFixture(arena, 62.0f + 2.0f * t, t, b2Vec2(0.0f, 45.0f + t), 0.0f); // ceiling
        AddBoxFixture(arena, t, 22.5f, b2Vec2(-62.0f - t, 22.5f), 0.0f);          // left wall
        AddBoxFixture(arena, t, 22.5f, b2Vec2(62.0f + t, 22.5f), 0.0f);           // right wall

        // Slotted thin walls: 2 m segments, 1 m slots.
        for (float x : {20.0f, 32.0f})
        {
            const float shift = (x > 25.0f) ? 1.5f : 0.0f;
            for (float bottom = shift; bottom + 2.0f <= 23.0f + shift; bottom += 3.0f)
            {
                for (float side : {-1.0f, 1.0f})
                {
                    AddBoxFixture(arena, 0.05f, 1.0f, b2Vec2(side * x, bottom + 1.0f), 0.0f);
                }
            }
        }
    }

    AddBoxPyramid(world, 16, -0.5f * 1.125f * 15.0f, 0.75f);

    Gun gun;
    gun.size = size;
    gun.rng = Rng(seed);
    gun.bullets.assign(static_cast<size_t>(size), nullptr);
    scene.perStep = [gun](b2World& w, int step) mutable {
        gun.Step(w, step);
    };
    return scene;
}

} // namespace quadphase::scenes::detail
