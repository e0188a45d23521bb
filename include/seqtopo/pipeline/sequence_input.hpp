#pragma once
// What a sequence comes from (INTERFACE.md, "INPUT kinds"), and the listing of an image folder.
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace seqtopo::pipeline {

enum class InputKind { automatic, images, video, descriptors, similarity };

// "auto", "images", "video", "descriptors", "similarity"; throws std::invalid_argument otherwise.
InputKind parse_input_kind(std::string_view name);
std::string_view input_kind_name(InputKind kind);

struct SequenceInput {
  std::filesystem::path path;
  InputKind kind = InputKind::automatic;
  std::size_t every = 1;  // video: keep frames 0, K, 2K, ...
};

// The kind `automatic` stands for: a folder holds images; a .npy file whose name contains "similarity" is a
// similarity matrix, any other .npy holds descriptors; any other file is read as a video. Throws
// InputError naming the path when it does not exist.
InputKind resolve_input_kind(const SequenceInput& input);

// Natural order of file names: runs of digits compare by value ("2.jpg" < "10.jpg"), other characters
// case-insensitively; names equal under that rule fall back to plain byte order so the order is total.
bool natural_less(std::string_view a, std::string_view b);

// The image files of a folder (by extension: png, jpg, jpeg, bmp, tif, tiff, webp, pgm, ppm, pnm, jp2),
// in natural order. Hidden files and files whose name starts with "ground_truth" are skipped: a
// ground-truth matrix often sits beside the images and is not part of the sequence. Throws InputError
// naming the folder when it cannot be read or holds no image.
std::vector<std::filesystem::path> list_images(const std::filesystem::path& folder);

}  // namespace seqtopo::pipeline
