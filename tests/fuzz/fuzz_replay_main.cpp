// SPDX-License-Identifier: MIT
// Replays fuzz inputs through the fuzz target without libFuzzer: each argument is a file or a directory of
// files (not recursive). Every normal test run replays the committed corpus (tests/fuzz/corpus) this way, so
// the corpus is exercised with any compiler. A divergence aborts (see broadphase_fuzz.cpp). Exit status 1
// when an argument cannot be read or no input was found.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace
{

bool Replay(const std::filesystem::path& file)
{
    std::ifstream in(file, std::ios::binary);
    if (!in)
    {
        std::fprintf(stderr, "qp_fuzz_replay: cannot read %s\n", file.string().c_str());
        return false;
    }
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    return true;
}

} // namespace

int main(int argc, char** argv)
{
    if (argc < 2)
    {
        std::fprintf(stderr, "usage: %s <file or directory>...\n", argv[0]);
        return 1;
    }
    int inputs = 0;
    for (int i = 1; i < argc; ++i)
    {
        const std::filesystem::path path(argv[i]);
        std::error_code error;
        if (std::filesystem::is_directory(path, error))
        {
            std::vector<std::filesystem::path> files;
            for (const auto& entry : std::filesystem::directory_iterator(path))
            {
                if (entry.is_regular_file())
                {
                    files.push_back(entry.path());
                }
            }
            std::sort(files.begin(), files.end());
            for (const auto& file : files)
            {
                if (!Replay(file))
                {
                    return 1;
                }
                ++inputs;
            }
        }
        else
        {
            if (!Replay(path))
            {
                return 1;
            }
            ++inputs;
        }
    }
    if (inputs == 0)
    {
        std::fprintf(stderr, "qp_fuzz_replay: no input found\n");
        return 1;
    }
    std::printf("qp_fuzz_replay: %d inputs replayed, no divergence\n", inputs);
    return 0;
}
