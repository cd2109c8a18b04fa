// SPDX-License-Identifier: MIT
// qp_trace_to_input: converts a recorded broadphase trace (bench/'s qp-record, quadphase/trace.h) into an
// input of the Box2D-level fuzz target (box2d_fuzz.cpp), so that the fuzzer starts from the calls real scenes
// make: boxes and displacements bit for bit, proxies named by their recorded ids.
//
//   qp_trace_to_input TRACE OUT [--config BYTE] [--max-bytes N]
//
// --config: the target's first byte (validation, depth, threads; default 0: automatic depth, 1 thread).
// --max-bytes: stop before the call that would pass N bytes (default 4096; libFuzzer's inputs stay short), at
// a call boundary; the target ends every input with UpdatePairs and a full check. Exit status 1 on a bad
// trace or a trace the format cannot express (ids above 32767, more live proxies than the target keeps).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "box2d_fuzz_format.h"
#include "fuzz_input.h"
#include "trace.h"

namespace
{

namespace op = quadphase::fuzz::box2d_op;

constexpr int kTargetMaxLive = 600; // box2d_fuzz.cpp's kMaxLive

void PutFloat(std::vector<uint8_t>& out, float f)
{
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    for (int i = 0; i < 4; ++i)
    {
        out.push_back(uint8_t(bits >> (8 * i)));
    }
}

void PutBox(std::vector<uint8_t>& out, const quadphase::Box& b)
{
    out.push_back(quadphase::fuzz::kRawBox);
    PutFloat(out, b.minX);
    PutFloat(out, b.minY);
    PutFloat(out, b.maxX);
    PutFloat(out, b.maxY);
}

void PutVector(std::vector<uint8_t>& out, quadphase::Vec2 v)
{
    out.push_back(quadphase::fuzz::kRawBox);
    PutFloat(out, v.x);
    PutFloat(out, v.y);
}

void PutId(std::vector<uint8_t>& out, int32_t id)
{
    const uint16_t v = uint16_t(op::kDirectId | uint16_t(id));
    out.push_back(uint8_t(v & 0xff));
    out.push_back(uint8_t(v >> 8));
}

int Usage()
{
    std::fprintf(stderr, "usage: qp_trace_to_input TRACE OUT [--config BYTE] [--max-bytes N]\n");
    return 2;
}

} // namespace

int main(int argc, char** argv)
{
    if (argc < 3)
    {
        return Usage();
    }
    int config = 0;
    size_t maxBytes = 4096;
    for (int i = 3; i < argc; ++i)
    {
        const std::string arg = argv[i];
        if (arg == "--config" && i + 1 < argc)
        {
            config = std::atoi(argv[++i]);
        }
        else if (arg == "--max-bytes" && i + 1 < argc)
        {
            maxBytes = size_t(std::atol(argv[++i]));
        }
        else
        {
            return Usage();
        }
    }
    if (config < 0 || config > 255)
    {
        std::fprintf(stderr, "qp_trace_to_input: --config must be 0..255\n");
        return 2;
    }

    quadphase::Trace trace;
    std::string error;
    if (!trace.Load(argv[1], error))
    {
        std::fprintf(stderr, "qp_trace_to_input: %s: %s\n", argv[1], error.c_str());
        return 1;
    }

    std::vector<uint8_t> out{uint8_t(config)};
    std::vector<uint8_t> call;
    int live = 0;
    size_t calls = 0;
    for (const quadphase::TraceOp& t : trace.Ops())
    {
        call.clear();
        if (t.id > 0x7fff)
        {
            std::fprintf(stderr, "qp_trace_to_input: id %d does not fit the format (at most 32767)\n", t.id);
            return 1;
        }
        switch (t.kind)
        {
        case quadphase::TraceOp::Create:
            if (++live > kTargetMaxLive)
            {
                std::fprintf(stderr, "qp_trace_to_input: more than %d live proxies\n", kTargetMaxLive);
                return 1;
            }
            call.push_back(op::Code(op::kCreate));
            PutBox(call, t.box);
            break;
        case quadphase::TraceOp::Destroy:
            --live;
            call.push_back(op::Code(op::kDestroy));
            PutId(call, t.id);
            break;
        case quadphase::TraceOp::Move:
            call.push_back(op::Code(op::kMove));
            PutId(call, t.id);
            call.push_back(0); // flags: the box follows, no comparison now
            PutVector(call, t.displacement);
            PutBox(call, t.box);
            break;
        case quadphase::TraceOp::Touch:
            call.push_back(op::Code(op::kTouch));
            PutId(call, t.id);
            break;
        case quadphase::TraceOp::UpdatePairs:
            call.push_back(op::Code(op::kUpdatePairs));
            break;
        case quadphase::TraceOp::ShiftOrigin:
            call.push_back(op::Code(op::kShiftOrigin));
            PutVector(call, t.displacement);
            break;
        default:
            std::fprintf(stderr, "qp_trace_to_input: unknown call kind %d\n", int(t.kind));
            return 1;
        }
        if (out.size() + call.size() > maxBytes)
        {
            break;
        }
        out.insert(out.end(), call.begin(), call.end());
        ++calls;
    }

    std::ofstream file(argv[2], std::ios::binary);
    file.write(reinterpret_cast<const char*>(out.data()), std::streamsize(out.size()));
    if (!file)
    {
        std::fprintf(stderr, "qp_trace_to_input: cannot write %s\n", argv[2]);
        return 1;
    }
    std::printf("qp_trace_to_input: %zu of %zu calls, %zu bytes -> %s\n", calls, trace.Ops().size(),
                out.size(), argv[2]);
    return 0;
}
