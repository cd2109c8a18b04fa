// SPDX-License-Identifier: MIT
// The command line of the tools: "--key value", "--key=value" and "--flag" options, parsed by CLI11. The usage
// text stays the tool's own (Check prints it), so every tool documents its options in one place.
#pragma once

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace quadphase::tools
{

class Args
{
public:
    /// `options` take one value each time they are given (the last one wins for Get; GetAll returns all),
    /// `flags` take none ("help" is always a flag); anything else is a problem that Check() reports. `tool`
    /// names the messages.
    Args(int argc, char** argv, std::string tool, const std::vector<std::string>& options,
         std::vector<std::string> flags = {})
        : m_tool(std::move(tool))
    {
        CLI::App app(m_tool);
        app.set_help_flag();
        flags.push_back("help");
        for (const std::string& name : options)
        {
            app.add_option("--" + name, m_values[name])
                ->allow_extra_args(false)
                ->expected(1)
                ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
        }
        for (const std::string& name : flags)
        {
            app.add_flag("--" + name, m_flags[name]);
        }
        try
        {
            app.parse(argc, argv);
        }
        catch (const CLI::ParseError& e)
        {
            m_error = e.what();
        }
    }

    /// With --help, a problem (unknown option, missing value) or `ok` false: prints the problem and the
    /// printf-style usage to stderr and exits, 0 for --help, else 2.
    __attribute__((format(printf, 3, 4))) void Check(bool ok, const char* usage, ...) const
    {
        if (ok && m_error.empty() && !Has("help"))
        {
            return;
        }
        if (!m_error.empty())
        {
            std::fprintf(stderr, "%s: %s\n", m_tool.c_str(), m_error.c_str());
        }
        va_list args;
        va_start(args, usage);
        std::vfprintf(stderr, usage, args);
        va_end(args);
        std::exit(Has("help") ? 0 : 2);
    }

    bool Has(const std::string& key) const
    {
        const auto flag = m_flags.find(key);
        return flag != m_flags.end() ? flag->second > 0 : !GetAll(key).empty();
    }
    std::string Get(const std::string& key, const std::string& fallback = "") const
    {
        const std::vector<std::string> all = GetAll(key);
        return all.empty() ? fallback : all.back(); // the last one wins
    }
    std::vector<std::string> GetAll(const std::string& key) const
    {
        const auto it = m_values.find(key);
        return it == m_values.end() ? std::vector<std::string>{} : it->second;
    }
    long GetInt(const std::string& key, long fallback) const
    {
        return long(GetNumber(key, double(fallback), true));
    }
    double GetDouble(const std::string& key, double fallback) const
    {
        return GetNumber(key, fallback, false);
    }
    /// GetInt, and exits with a message when the value is outside [lo, hi].
    long GetIntIn(const std::string& key, long fallback, long lo, long hi) const
    {
        const long x = GetInt(key, fallback);
        if (x < lo || x > hi)
        {
            std::fprintf(stderr, "--%s must be an integer in [%ld, %ld], got %ld\n", key.c_str(), lo, hi, x);
            std::exit(2);
        }
        return x;
    }

private:
    /// The option's value as a number (exits with a message when it is not one, or not an integer when
    /// asked).
    double GetNumber(const std::string& key, double fallback, bool integer) const
    {
        const std::string v = Get(key);
        if (v.empty())
        {
            return fallback;
        }
        char* end = nullptr;
        const double x = integer ? double(std::strtol(v.c_str(), &end, 10)) : std::strtod(v.c_str(), &end);
        if (end == v.c_str() || *end != '\0' || !std::isfinite(x))
        {
            std::fprintf(stderr, "--%s: '%s' is not %s\n", key.c_str(), v.c_str(),
                         integer ? "an integer" : "a number");
            std::exit(2);
        }
        return x;
    }

    std::string m_tool;
    std::map<std::string, std::vector<std::string>> m_values;
    std::map<std::string, int> m_flags;
    std::string m_error;
};

} // namespace quadphase::tools
