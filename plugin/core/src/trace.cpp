// SPDX-License-Identifier: MIT
// Trace: saving and loading recorded broadphase calls (the binary file format), and counting their UpdatePairs.
#include "trace.h"

#include <cstdio>
#include <cstring>
#include <memory>

namespace quadphase
{
namespace
{

constexpr char kMagic[8] = {'Q', 'P', 'T', 'R', 'A', 'C', 'E', '1'};

struct FileCloser
{
    void operator()(std::FILE* f) const { std::fclose(f); }
};

} // namespace

int64_t Trace::UpdatePairsCount() const
{
    int64_t count = 0;
    for (const TraceOp& op : m_ops)
    {
        count += op.kind == TraceOp::UpdatePairs ? 1 : 0;
    }
    return count;
}

bool Trace::Save(const std::string& path, std::string& error) const
{
    std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
    if (!file)
    {
        error = "cannot open " + path + " for writing";
        return false;
    }
    const uint64_t count = m_ops.size();
    const bool ok = std::fwrite(kMagic, sizeof(kMagic), 1, file.get()) == 1 &&
                    std::fwrite(&count, sizeof(count), 1, file.get()) == 1 &&
                    (count == 0 || std::fwrite(m_ops.data(), sizeof(TraceOp), count, file.get()) == count);
    if (!ok)
    {
        error = "cannot write " + path;
    }
    return ok;
}

bool Trace::Load(const std::string& path, std::string& error)
{
    std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
    if (!file)
    {
        error = "cannot open " + path;
        return false;
    }
    char magic[sizeof(kMagic)];
    uint64_t count = 0;
    if (std::fread(magic, sizeof(magic), 1, file.get()) != 1 ||
        std::memcmp(magic, kMagic, sizeof(kMagic)) != 0 ||
        std::fread(&count, sizeof(count), 1, file.get()) != 1)
    {
        error = path + " is not a quadphase trace";
        return false;
    }
    m_ops.resize(count);
    if (count != 0 && std::fread(m_ops.data(), sizeof(TraceOp), count, file.get()) != count)
    {
        error = path + " is truncated";
        m_ops.clear();
        return false;
    }
    for (const TraceOp& op : m_ops)
    {
        if (op.kind > TraceOp::ShiftOrigin)
        {
            error = path + " holds an unknown operation";
            m_ops.clear();
            return false;
        }
    }
    return true;
}

} // namespace quadphase
