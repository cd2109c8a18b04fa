// SPDX-License-Identifier: MIT
// Scene registry, name parsing, stepping and hashing helpers.
#include "quadphase_scenes/scenes.h"

#include <cctype>
#include <cstring>
#include <stdexcept>

#include "scene_common.h"

namespace quadphase::scenes
{

const std::vector<SceneInfo>& AllScenes()
{
    static const std::vector<SceneInfo> scenes = {
        {SceneId::Pyramid, "pyramid",
         "pyramid of unit boxes stacked on a ground edge (Box2D testbed Pyramid)", "boxes on the bottom row",
         1, 200, 20},
        {SceneId::Rain, "rain", "mixed circles and boxes dropped from a grid into a wide open-top container",
         "falling bodies", 1, 65536, 16000},
        {SceneId::Tumbler, "tumbler",
         "motor-driven rotating hollow box filled with small boxes spawned over the first 200 steps",
         "small boxes", 1, 800, 800},
        {SceneId::Tiles, "tiles",
         "static ground of 1x1 tiles (10 columns per row) with a 20-box pyramid on top", "static tiles", 100,
         100000, 4000},
        {SceneId::Particles, "particles",
         "elastic circles (r 0.5, 1-5 m/s) in a closed box, no gravity, area fraction 0.15", "circles", 2,
         200000, 10000},
        {SceneId::Bullets, "bullets",
         "fast bullet bodies fired through slotted thin walls at a box pile, relaunched every 2 s", "bullets",
         1, 4000, 500},
        {SceneId::Sparse, "sparse",
         "moving bodies and static rocks spread over a large closed world (one per 400 m^2), no gravity",
         "moving bodies", 1, 100000, 4000},
        {SceneId::Shooter, "shooter",
         "top-down shooter: enemies chase a circling player who fires bullets (destroyed after 0.75 s)",
         "enemies", 1, 20000, 400},
        {SceneId::OpenWorld, "openworld",
         "vehicles driving through towns of static buildings, map centred ~50 km from the origin, no gravity",
         "vehicles", 1, 100000, 2000},
        {SceneId::Mixed, "mixed",
         "pebbles, crates and boulders (radii 0.05-3.5 m) falling onto a 20 km ground", "falling bodies", 1,
         50000, 3000},
        {SceneId::Terrain, "terrain",
         "circles and polygons rolling down a chain-shape landscape of rolling hills", "rolling bodies", 1,
         20000, 1000},
        {SceneId::Churn, "churn",
         "bodies in a container; every step N/120 (at least 1) are destroyed and as many created",
         "live bodies", 1, 50000, 2000},
    };
    return scenes;
}

const SceneInfo& GetSceneInfo(SceneId id)
{
    for (const SceneInfo& info : AllScenes())
    {
        if (info.id == id)
        {
            return info;
        }
    }
    throw std::invalid_argument("quadphase::scenes: unknown SceneId");
}

const char* SceneName(SceneId id)
{
    return GetSceneInfo(id).name;
}

std::optional<SceneId> ParseSceneName(std::string_view name)
{
    for (const SceneInfo& info : AllScenes())
    {
        const size_t length = std::strlen(info.name);
        if (length != name.size())
        {
            continue;
        }
        bool same = true;
        for (size_t i = 0; i < length && same; ++i)
        {
            same =
                std::tolower(static_cast<unsigned char>(name[i])) == static_cast<unsigned char>(info.name[i]);
        }
        if (same)
        {
            return info.id;
        }
    }
    return std::nullopt;
}

std::string SceneNameList()
{
    std::string list;
    for (const SceneInfo& info : AllScenes())
    {
        if (!list.empty())
        {
            list += ", ";
        }
        list += info.name;
    }
    return list;
}

Scene BuildScene(SceneId id, int size, uint32_t seed)
{
    const SceneInfo& info = GetSceneInfo(id);
    if (size < info.minSize || size > info.maxSize)
    {
        throw std::invalid_argument("quadphase::scenes: size " + std::to_string(size) + " of scene '" +
                                    info.name + "' is outside [" + std::to_string(info.minSize) + ", " +
                                    std::to_string(info.maxSize) + "]");
    }
    switch (id)
    {
    case SceneId::Pyramid:
        return detail::BuildPyramid(size, seed);
    case SceneId::Rain:
        return detail::BuildRain(size, seed);
    case SceneId::Tumbler:
        return detail::BuildTumbler(size, seed);
    case SceneId::Tiles:
        return detail::BuildTiles(size, seed);
    case SceneId::Particles:
        return detail::BuildParticles(size, seed);
    case SceneId::Bullets:
        return detail::BuildBullets(size, seed);
    case SceneId::Sparse:
        return detail::BuildSparse(size, seed);
    case SceneId::Shooter:
        return detail::BuildShooter(size, seed);
    case SceneId::OpenWorld:
        return detail::BuildOpenWorld(size, seed);
    case SceneId::Mixed:
        return detail::BuildMixed(size, seed);
    case SceneId::Terrain:
        return detail::BuildTerrain(size, seed);
    case SceneId::Churn:
        return detail::BuildChurn(size, seed);
    }
    throw std::invalid_argument("quadphase::scenes: unknown SceneId");
}

std::unique_ptr<b2World> BuildSceneWorld(SceneId id, int size, uint32_t seed)
{
    return BuildScene(id, size, seed).world;
}

void StepScene(Scene& scene)
{
    scene.world->Step(scene.timeStep, scene.velocityIterations, scene.positionIterations);
    if (scene.perStep)
    {
        scene.perStep(*scene.world, scene.stepCount);
    }
    ++scene.stepCount;
}

b2Body* AddBody(b2World& world, b2BodyType type, b2Vec2 position, const b2Shape& shape, b2FixtureDef material)
{
    b2BodyDef bd;
    bd.type = type;
    bd.position = position;
    b2Body* body = world.CreateBody(&bd);
    material.shape = &shape;
    body->CreateFixture(&material);
    return body;
}

int32_t CountBodies(const b2World& world)
{
    return world.GetBodyCount();
}

int32_t CountFixtures(const b2World& world)
{
    int32_t count = 0;
    for (const b2Body* body = world.GetBodyList(); body != nullptr; body = body->GetNext())
    {
        for (const b2Fixture* fixture = body->GetFixtureList(); fixture != nullptr;
             fixture = fixture->GetNext())
        {
            ++count;
        }
    }
    return count;
}

namespace
{
void HashBytes(uint64_t& hash, const void* data, size_t size)
{
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i)
    {
        hash ^= bytes[i];
        hash *= 1099511628211ull;
    }
}

void HashFloat(uint64_t& hash, float value)
{
    uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    HashBytes(hash, &bits, sizeof bits);
}
} // namespace

uint64_t HashBodyPositions(const b2World& world)
{
    uint64_t hash = 14695981039346656037ull;
    for (const b2Body* body = world.GetBodyList(); body != nullptr; body = body->GetNext())
    {
        const b2Vec2& p = body->GetPosition();
        HashFloat(hash, p.x);
        HashFloat(hash, p.y);
        HashFloat(hash, body->GetAngle());
    }
    return hash;
}

std::vector<uint32_t> BodyStateBits(const b2World& world)
{
    std::vector<uint32_t> bits;
    for (const b2Body* body = world.GetBodyList(); body != nullptr; body = body->GetNext())
    {
        for (float value :
             {body->GetPosition().x, body->GetPosition().y, body->GetAngle(), body->GetLinearVelocity().x,
              body->GetLinearVelocity().y, body->GetAngularVelocity()})
        {
            uint32_t word;
            std::memcpy(&word, &value, sizeof word);
            bits.push_back(word);
        }
    }
    return bits;
}

// ---------------------------------------------------------------------------------------------------------------
// Rng

Rng::Rng(uint32_t seed) : m_engine(seed) {}

uint32_t Rng::NextU32()
{
    return static_cast<uint32_t>(m_engine()); // mt19937 yields exactly 32 bits, specified by the standard
}

float Rng::Uniform01()
{
    return static_cast<float>(NextU32() >> 8) * (1.0f / 16777216.0f);
}

float Rng::Uniform(float lo, float hi)
{
    return lo + (hi - lo) * Uniform01();
}

uint32_t Rng::Index(uint32_t n)
{
    return static_cast<uint32_t>((static_cast<uint64_t>(NextU32()) * n) >> 32);
}

void Rng::Shuffle(std::vector<int32_t>& values)
{
    for (size_t i = values.size(); i > 1; --i)
    {
        const uint32_t j = Index(static_cast<uint32_t>(i));
        std::swap(values[i - 1], values[j]);
    }
}

namespace detail
{

void AddBoxPyramid(b2World& world, int base, float x0, float y0)
{
    b2PolygonShape shape;
    shape.SetAsBox(0.5f, 0.5f);
    b2FixtureDef material;
    material.density = 5.0f;

    // Testbed spacing: rows shift right by half a box plus a gap, boxes are 1.125 apart.
    const b2Vec2 deltaRow(0.5625f, 1.25f);
    const b2Vec2 deltaColumn(1.125f, 0.0f);
    b2Vec2 rowStart(x0, y0);
    for (int row = 0; row < base; ++row)
    {
        b2Vec2 position = rowStart;
        for (int column = row; column < base; ++column)
        {
            AddBody(world, b2_dynamicBody, position, shape, material);
            position += deltaColumn;
        }
        rowStart += deltaRow;
    }
}

} // namespace detail

} // namespace quadphase::scenes
