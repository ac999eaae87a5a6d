// Where a file a script names (a sport's field, a sound, a recorded phrase, a module, a power-up)
// is looked for: below the folders the engine lets that name reach, and nowhere else. A sport is
// shared between venues, so its names must not reach the machine's other files, nor a device or
// a FIFO that would block the load on opening it. docs/lua-api.md, "Paths".
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace quantum::lua {

// The first of `folders` holding `name` (a relative path, e.g. "field.lua" or "sounds/horn.wav"),
// or an empty path when none does; `looked` gets every place tried, for the caller's message.
// Throws ReadError naming `key` (the sport's key, e.g. "audio.sounds.shot") when `name` is
// absolute, has a ".." part, or leads, symlinks followed, out of `folders`, or when what it names
// is not a regular file (a device, a FIFO, a directory, a socket). Nothing is opened: the file's
// type is looked at first.
std::filesystem::path confined_path(const std::vector<std::filesystem::path>& folders, const std::string& name,
                                    const std::string& key, std::string& looked);

}  // namespace quantum::lua
