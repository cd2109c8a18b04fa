// Package smoke test shared by tests/package/*_consumer.
//
// Creates a b2World with two overlapping dynamic boxes (and one far away),
// steps it, and checks that exactly one touching contact exists.  Exits
// non-zero otherwise.  Built against quadphase::box2d (QUADPHASE_VARIANT_QUADPHASE)
// or quadphase::box2d_stock (QUADPHASE_VARIANT_STOCK).
#include <box2d/box2d.h>
#if defined(QUADPHASE_VARIANT_QUADPHASE)
#include <quadphase/box2d.h>
#define CONSUMER_VARIANT "quadphase"
#elif defined(QUADPHASE_VARIANT_STOCK)
#define CONSUMER_VARIANT "stock"
#else
#error "define QUADPHASE_VARIANT_QUADPHASE or QUADPHASE_VARIANT_STOCK"
#endif

#include <cstdio>

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

    std::printf("consumer (%s): %d contact(s), %d touching, GetContactCount()=%d, pair %s\n", CONSUMER_VARIANT,
                contacts, touching, world.GetContactCount(), pairOk ? "found" : "MISSING");
    const bool ok = contacts == 1 && touching == 1 && pairOk && world.GetContactCount() == 1;
    std::printf("consumer (%s): %s\n", CONSUMER_VARIANT, ok ? "OK" : "FAILED");
    return ok ? 0 : 1;
}
