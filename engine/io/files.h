#pragma once
// Writing outputs so that a failure leaves no half-written file: through a temporary name in the
// same folder, then a rename. No device needed (the graph editor's saves use it too).
#include <filesystem>
#include <string>

namespace caustica::io {

// Throws InputError before any work is done when the output's folder does not exist.
void check_output_file(const std::string& path);

// A name beside `target` (so that rename is atomic) with the same extension (image writers pick the
// format by it).
std::filesystem::path temporary_name(const std::filesystem::path& target);

// Renames the temporary file over `target`; on failure removes it and throws InputError.
void commit(const std::filesystem::path& temp, const std::filesystem::path& target);

// Writes text through a temporary file and a rename.
void write_text_atomically(const std::string& path, const std::string& text);

}  // namespace caustica::io
