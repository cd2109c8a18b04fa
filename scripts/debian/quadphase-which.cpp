// SPDX-License-Identifier: MIT
// quadphase-which PROGRAM...: which libbox2d.so.2 each program loads, as the dynamic loader resolves it (ldd, so with
// the caller's LD_LIBRARY_PATH and the program's run paths), and whether that file is quadphase's or stock Box2D's.
// A library is quadphase's when its dynamic symbol table defines quadphase::GetStats(b2World const&), a documented
// extras function (<quadphase/box2d.h>) that stock Box2D does not have. Part of the Debian packages (scripts/deb.sh).
#include <elf.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace
{

const char* const kLibrary = "libbox2d.so.2";
const char* const kMarker = "_ZN9quadphase8GetStatsERK7b2World"; // quadphase::GetStats(b2World const&)

// Runs argv (looked up on PATH, no shell) and returns its standard output; `ok` is false unless it exited with 0.
std::string Run(const std::vector<std::string>& args, bool& ok)
{
    ok = false;
    std::vector<char*> argv;
    for (const std::string& arg : args)
        argv.push_back(const_cast<char*>(arg.c_str()));
    argv.push_back(nullptr);
    int fds[2];
    if (pipe(fds) != 0)
        return "";
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, fds[0]);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    pid_t pid = 0;
    const int spawned = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(fds[1]);
    std::string out;
    char buffer[4096];
    ssize_t n = 0;
    while ((n = read(fds[0], buffer, sizeof buffer)) > 0)
        out.append(buffer, static_cast<size_t>(n));
    close(fds[0]);
    int status = 0;
    ok = spawned == 0 && waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
    return out;
}

// Whether the ELF file defines `symbol` in its dynamic symbol table. Sets `error` when the file is not a readable
// 64-bit ELF file.
bool DefinesDynamicSymbol(const std::string& path, const char* symbol, std::string& error)
{
    const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
    struct stat st = {};
    if (fd < 0 || fstat(fd, &st) != 0 || static_cast<size_t>(st.st_size) < sizeof(Elf64_Ehdr))
    {
        error = std::string("cannot read ") + path + ": " + std::strerror(errno);
        if (fd >= 0)
            close(fd);
        return false;
    }
    const size_t size = static_cast<size_t>(st.st_size);
    void* map = mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
    close(fd);
    if (map == MAP_FAILED)
    {
        error = std::string("cannot map ") + path + ": " + std::strerror(errno);
        return false;
    }
    const auto* base = static_cast<const unsigned char*>(map);
    const auto* header = static_cast<const Elf64_Ehdr*>(map);
    bool found = false;
    if (std::memcmp(header->e_ident, ELFMAG, SELFMAG) != 0 || header->e_ident[EI_CLASS] != ELFCLASS64 ||
        header->e_shoff + size_t{header->e_shnum} * sizeof(Elf64_Shdr) > size)
    {
        error = path + " is not a 64-bit ELF file";
    }
    else
    {
        const auto* sections = reinterpret_cast<const Elf64_Shdr*>(base + header->e_shoff);
        for (unsigned i = 0; i < header->e_shnum && !found; ++i)
        {
            const Elf64_Shdr& symtab = sections[i];
            if (symtab.sh_type != SHT_DYNSYM || symtab.sh_link >= header->e_shnum)
                continue;
            const Elf64_Shdr& strtab = sections[symtab.sh_link];
            if (symtab.sh_offset + symtab.sh_size > size || strtab.sh_offset + strtab.sh_size > size)
                break;
            const auto* symbols = reinterpret_cast<const Elf64_Sym*>(base + symtab.sh_offset);
            const char* names = reinterpret_cast<const char*>(base + strtab.sh_offset);
            for (size_t s = 0; s < symtab.sh_size / sizeof(Elf64_Sym) && !found; ++s)
            {
                const Elf64_Sym& sym = symbols[s];
                found = sym.st_shndx != SHN_UNDEF && sym.st_name < strtab.sh_size &&
                        std::strncmp(names + sym.st_name, symbol, strtab.sh_size - sym.st_name) == 0;
            }
        }
    }
    munmap(map, size);
    return found;
}

// "PACKAGE VERSION" of the Debian package that owns `path`, or "" when none does.
std::string OwningPackage(const std::string& path)
{
    bool ok = false;
    const std::string owner = Run({"dpkg-query", "--search", path}, ok);
    if (!ok)
        return "";
    std::string package = owner.substr(0, owner.find(':'));
    const std::string version = Run({"dpkg-query", "--show", "--showformat=${Version}", package}, ok);
    return ok ? package + " " + version : package;
}

// One line about `program`; returns false when no libbox2d.so.2 could be identified.
bool Report(const std::string& program)
{
    bool ok = false;
    std::istringstream ldd(Run({"ldd", program}, ok));
    if (!ok)
    {
        std::printf("%s: ldd failed (not a dynamically linked program?)\n", program.c_str());
        return false;
    }
    std::string line;
    std::string path;
    while (std::getline(ldd, line))
    {
        std::istringstream words(line);
        std::string name, arrow;
        if (words >> name >> arrow && name == kLibrary && arrow == "=>")
        {
            words >> path;
            break;
        }
    }
    if (path.empty() || path == "not")
    {
        std::printf("%s: %s\n", program.c_str(),
                    path.empty() ? "does not load libbox2d.so.2" : "libbox2d.so.2 not found");
        return false;
    }
    char* real = realpath(path.c_str(), nullptr);
    const std::string file = real ? real : path;
    std::free(real);
    std::string error;
    const bool quadphase = DefinesDynamicSymbol(file, kMarker, error);
    if (!error.empty())
    {
        std::printf("%s: libbox2d.so.2 => %s: %s\n", program.c_str(), path.c_str(), error.c_str());
        return false;
    }
    // Box2D's version from the real file's name (libbox2d.so.2.4.1).
    const std::string prefix = "libbox2d.so.";
    const size_t at = file.rfind(prefix);
    const std::string version = at == std::string::npos ? "?" : file.substr(at + prefix.size());
    const std::string package = OwningPackage(file);
    std::printf("%s: libbox2d.so.2 => %s (%s): %s, Box2D %s, %s\n", program.c_str(), path.c_str(),
                file.c_str(), quadphase ? "quadphase" : "stock", version.c_str(),
                package.empty() ? "not from a package" : ("package " + package).c_str());
    return true;
}

} // namespace

int main(int argc, char** argv)
{
    if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)
    {
        std::fprintf(
            argc < 2 ? stderr : stdout,
            "usage: quadphase-which PROGRAM...\n"
            "Says which libbox2d.so.2 each program loads (as ldd resolves it) and whether it is\n"
            "quadphase's (it exports quadphase::GetStats) or stock Box2D, with its version and path.\n");
        return argc < 2 ? 2 : 0;
    }
    bool all = true;
    for (int i = 1; i < argc; ++i)
        all = Report(argv[i]) && all;
    return all ? 0 : 1;
}
