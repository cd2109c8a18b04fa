// SPDX-License-Identifier: MIT
// JSON lines of the tools, written with nlohmann-json: one flat object per measurement, keys in the order
// written, numbers to 9 significant digits (whole ones as integers; null when not finite).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

namespace quadphase::tools
{

class JsonLine
{
public:
    JsonLine& Str(const char* key, const std::string& value) { return Set(key, value); }
    JsonLine& Int(const char* key, int64_t value) { return Set(key, value); }
    /// A number to 9 significant digits; null when it is not finite.
    JsonLine& Num(const char* key, double value) { return Set(key, Round(value)); }
    /// A value already written as JSON (null, an object).
    JsonLine& Raw(const char* key, const std::string& json)
    {
        return Set(key, nlohmann::ordered_json::parse(json));
    }
    /// An array of numbers, from any range (a vector, a plain array).
    template <typename Range>
    JsonLine& Array(const char* key, const Range& values)
    {
        nlohmann::ordered_json list = nlohmann::ordered_json::array();
        for (const auto& value : values)
        {
            list.push_back(Round(double(value)));
        }
        return Set(key, std::move(list));
    }
    std::string Text() const
    {
        return m_json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
    }

private:
    static nlohmann::ordered_json Round(double value)
    {
        if (!std::isfinite(value))
        {
            return nullptr;
        }
        char buf[64];
        std::snprintf(buf, sizeof(buf), "%.9g", value);
        // A whole number stays one ("64", not "64.0"): readers keep the type they always got.
        if (std::strpbrk(buf, ".eE") == nullptr)
        {
            return std::strtoll(buf, nullptr, 10);
        }
        return std::strtod(buf, nullptr);
    }
    template <typename T>
    JsonLine& Set(const char* key, T&& value)
    {
        m_json[key] = std::forward<T>(value);
        return *this;
    }

    nlohmann::ordered_json m_json = nlohmann::ordered_json::object();
};

/// Appends `line` and a newline to the file `path` (nothing when `path` is empty); exits with status 1 when it
/// cannot.
inline void AppendLine(const std::string& path, const std::string& line)
{
    if (path.empty())
    {
        return;
    }
    std::ofstream out(path, std::ios::app);
    out << line << '\n';
    if (!out)
    {
        std::fprintf(stderr, "cannot append to %s\n", path.c_str());
        std::exit(1);
    }
}

} // namespace quadphase::tools
