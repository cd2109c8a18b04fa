// SPDX-License-Identifier: MIT
// Package smoke test shared by tests/package/*_consumer.
//
// Creates a b2World with two overlapping dynamic boxes (and one far away),
// steps it, and checks that exactly one touching contact exists.  Exits
// non-zero otherwise.  Built against quadphase::box2d (QUADPHASE_VARIANT_QUADPHASE),
// quadphase::box2d_stock (QUADPHASE_VARIANT_STOCK), or Box2D's own package names
// (QUADPHASE_VARIANT_BOX2D_PACKAGE, C++11).
#include <box2d/box2d.h>
#if defined(QUADPHASE_VARIANT_QUADPHASE)
#include <quadphase/box2d.h>
#define CONSUMER_VARIANT "quadphase"
#elif defined(QUADPHASE_VARIANT_STOCK)
#define CONSUMER_VARIANT "stock"
#elif defined(QUADPHASE_VARIANT_BOX2D_PACKAGE)
// Box2D's own package names (find_package(box2d), pkg-config box2d): a C++11 game that includes only <box2d/box2d.h>.
// EXPECT_LIBRARY ("quadphase" or "stock") says which library the prefix must have given it; dlsym tells.
#include <dlfcn.h>
#define CONSUMER_VARIANT "box2d package"
#else
#error "define QUADPHASE_VARIANT_QUADPHASE, QUADPHASE_VARIANT_STOCK or QUADPHASE_VARIANT_BOX2D_PACKAGE"
#endif

#include <cstdio>
#include <cstring>

static b2Body* addBox(b2World& world, float x, float y)
{
    b2BodyDef def;
    def.type = b2_dynamicBody;
    def.position.Set(x, y);
    b2Body* body = world.CreateBody(&def);
    b2PolygonShape box;
    box.SetAsBox(1.0f, 1.0f);
    body->CreateFixture(&box, 1.0f);
    return body;
}

int main()
{
    b2World world(b2Vec2(0.0f, 0.0f));
    b2Body* a = addBox(world, 0.0f, 0.0f);
    b2Body* b = addBox(world, 0.5f, 0.25f);
    addBox(world, 20.0f, 20.0f); // far away: must not get a contact

    world.Step(1.0f / 60.0f, 8, 3);

    int contacts = 0;
    int touching = 0;
    bool pairOk = false;
    for (b2Contact* c = world.GetContactList(); c != nullptr; c = c->GetNext())
    {
        ++contacts;
        if (c->IsTouching())
        {
            ++touching;
        }
        b2Body* ba = c->GetFixtureA()->GetBody();
        b2Body* bb = c->GetFixtureB()->GetBody();
        if ((ba == a && bb == b) || (ba == b && bb == a))
        {
            pairOk = true;
        }
    }

    std::printf("consumer (%s): %d contact(s), %d touching, GetContactCount()=%d, pair %s\n",
                CONSUMER_VARIANT, contacts, touching, world.GetContactCount(), pairOk ? "found" : "MISSING");
    bool ok = contacts == 1 && touching == 1 && pairOk && world.GetContactCount() == 1;
#if defined(QUADPHASE_VARIANT_BOX2D_PACKAGE)
    // quadphase::SetValidation(b2BroadPhase&, bool): defined beside quadphase's b2BroadPhase, so a static link
    // (with -rdynamic) has it too.
    const bool quadphase = dlsym(RTLD_DEFAULT, "_ZN9quadphase13SetValidationER12b2BroadPhaseb") != nullptr;
    std::printf("consumer (%s): library %s, expected %s\n", CONSUMER_VARIANT,
                quadphase ? "quadphase" : "stock", EXPECT_LIBRARY);
    ok = ok && std::strcmp(quadphase ? "quadphase" : "stock", EXPECT_LIBRARY) == 0;
#endif
    std::printf("consumer (%s): %s\n", CONSUMER_VARIANT, ok ? "OK" : "FAILED");
    return ok ? 0 : 1;
}
