// SPDX-License-Identifier: MIT
// Internal helpers shared by the scene builders (not installed, not part of the API).
#pragma once

#include <cstdint>
#include <memory>

#include "box2d/box2d.h"
#include "quadphase_scenes/scenes.h"

namespace quadphase::scenes::detail
{

// One builder per scene, each in its own source file. `size` is already range-checked.
Scene BuildPyramid(int size, uint32_t seed);
Scene BuildRain(int size, uint32_t seed);
Scene BuildTumbler(int size, uint32_t seed);
Scene BuildTiles(int size, uint32_t seed);
Scene BuildParticles(int size, uint32_t seed);
Scene BuildBullets(int size, uint32_t seed);
Scene BuildSparse(int size, uint32_t seed);
Scene BuildShooter(int size, uint32_t seed);
Scene BuildOpenWorld(int size, uint32_t seed);
Scene BuildMixed(int size, uint32_t seed);
Scene BuildTerrain(int size, uint32_t seed);
Scene BuildChurn(int size, uint32_t seed);

/// A Scene with default stepping settings and a fresh world with the given gravity.
inline Scene MakeScene(SceneId id, int size, uint32_t seed, b2Vec2 gravity)
{
    Scene scene;
    scene.id = id;
    scene.size = size;
    scene.seed = seed;
    scene.world = std::make_unique<b2World>(gravity);
    return scene;
}

/// A fixture definition with this material (shape and filter left to the caller).
inline b2FixtureDef Material(float density, float friction, float restitution)
{
    b2FixtureDef fd;
    fd.density = density;
    fd.friction = friction;
    fd.restitution = restitution;
    return fd;
}

/// A static body at the origin (fixtures are added by the caller).
inline b2Body* CreateStaticBody(b2World& world, b2Vec2 position = b2Vec2(0.0f, 0.0f))
{
    b2BodyDef bd;
    bd.type = b2_staticBody;
    bd.position = position;
    return world.CreateBody(&bd);
}

/// Adds an axis-aligned box fixture (half extents hx, hy, centred at `center` in body coordinates).
inline b2Fixture* AddBoxFixture(b2Body* body, float hx, float hy, b2Vec2 center, float density,
                                float friction = 0.6f, float restitution = 0.0f, float angle = 0.0f)
{
    b2PolygonShape shape;
    shape.SetAsBox(hx, hy, center, angle);
    b2FixtureDef fd;
    fd.shape = &shape;
    fd.density = density;
    fd.friction = friction;
    fd.restitution = restitution;
    return body->CreateFixture(&fd);
}

/// Spawn points on a grid `pitch` apart, `columns` wide and centred on x = 0, its bottom row at y = y0: point i
/// is in row i / columns, column i % columns.
struct SpawnGrid
{
    float pitch;
    int columns;
    float y0;

    b2Vec2 At(int i) const
    {
        const float x0 = -0.5f * pitch * static_cast<float>(columns - 1);
        return b2Vec2(x0 + pitch * static_cast<float>(i % columns),
                      y0 + pitch * static_cast<float>(i / columns));
    }
};

/// Adds a circle fixture of `radius` centred on the body, made of `fd` (its shape is set here).
inline b2Fixture* AddCircleFixture(b2Body* body, float radius, b2FixtureDef fd)
{
    b2CircleShape circle;
    circle.m_radius = radius;
    fd.shape = &circle;
    return body->CreateFixture(&fd);
}

/// Adds a pyramid of unit boxes (side 1, density 5) in the style of Box2D's testbed: `base` boxes on the
/// bottom row, bottom-left box centred at (x0, y0).
void AddBoxPyramid(b2World& world, int base, float x0, float y0);

/// Gives `body` one fixture with `fd`'s material: a circle of radius in [rMin, rMax) or a box with half-extents in
/// [hMin, hMax), each with probability 1/2. Draws from `rng` in a fixed order (choice, then sizes).
inline void AddRandomCircleOrBox(b2Body* body, b2FixtureDef fd, Rng& rng, float rMin, float rMax, float hMin,
                                 float hMax)
{
    if (rng.Uniform01() < 0.5f)
    {
        AddCircleFixture(body, rng.Uniform(rMin, rMax), fd);
    }
    else
    {
        b2PolygonShape box;
        const float hx = rng.Uniform(hMin, hMax);
        const float hy = rng.Uniform(hMin, hMax);
        box.SetAsBox(hx, hy);
        fd.shape = &box;
        body->CreateFixture(&fd);
    }
}

} // namespace quadphase::scenes::detail
