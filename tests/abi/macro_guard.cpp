// SPDX-License-Identifier: MIT
// A game's translation unit: every public identifier of quadphase's core and extras (generated list, see
// tests/abi/CMakeLists.txt) defined as a macro before <box2d/box2d.h>, as games do with names like Config
// (caveexpress: #define Config ConfigManager::get()). Compiled as C++11 with -Wall -Wextra -Wpedantic -Werror,
// against stock Box2D's headers (the list must not break them) and against quadphase's (which must not use any of
// those names), then run: it steps a small world.
#include "macro_guard_defines.h"

#include <box2d/box2d.h>

#include <cstdio>

int main()
{
    b2World world(b2Vec2(0.0f, -10.0f));
    b2BodyDef def;
    def.type = b2_dynamicBody;
    b2Body* body = world.CreateBody(&def);
    b2PolygonShape box;
    box.SetAsBox(0.5f, 0.5f);
    body->CreateFixture(&box, 1.0f);
    for (int i = 0; i < 10; ++i)
    {
        world.Step(1.0f / 60.0f, 8, 3);
    }
    std::printf("macro guard: %d macros defined before <box2d/box2d.h>, %d proxies\n", QP_MACRO_GUARD_COUNT,
                world.GetProxyCount());
    return world.GetProxyCount() == 1 ? 0 : 1;
}
