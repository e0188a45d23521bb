#pragma once
// What a sequence comes from (INTERFACE.md, "INPUT kinds"), and the listing of an image folder.
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::pipeline {

// bag: a ROS 1 .bag, a ROS 2 .db3 or .mcap file, or a ROS 2 bag folder (metadata.yaml beside its .db3 or
// .mcap), read by the recording module (docs/recordings.md).
enum class InputKind { automatic, images, video, descriptors, similarity, bag };

// "auto", "images", "video", "descriptors", "similarity", "bag"; throws std::invalid_argument otherwise.
InputKind parse_input_kind(std::string_view name);
std::string_view input_kind_name(InputKind kind);

struct ImageListing;

struct SequenceInput {
  // {path}, {path, kind} and {path, kind, every} as before; the other settings are set by name.
  SequenceInput(std::filesystem::path p = {}, InputKind k = InputKind::automatic, std::size_t e = 1)
      : path(std::move(p)), kind(k), every(e) {}
  SequenceInput(const char* p) : SequenceInput(std::filesystem::path(p)) {}
  SequenceInput(const std::string& p) : SequenceInput(std::filesystem::path(p)) {}

  std::filesystem::path path;
  InputKind kind = InputKind::automatic;
  // Keep frames 0, K, 2K, ... of a video, bag, image folder (its listing) or descriptors.npy (its rows); the
  // poses, times and ground truth are then those of the frames kept. A similarity.npy refuses K > 1.
  std::size_t every = 1;
  // Image folders: also the images of every subfolder, in the order of list_images.
  bool recursive = false;
  // Image folders: an entry that looks like an image but cannot be read (a dangling or looping symbolic
  // link, a folder, a FIFO, a corrupt file) is left out with a warning instead of being an error.
  bool skip_unreadable = false;
  // Bags: the image topic (empty = the only image topic of the bag; several are an error listing them).
  std::string image_topic;
  // When not empty: only these frames of the sequence (indices after `every`, increasing), e.g. one frame
  // per D metres of odometry (recording/frame_selection.hpp).
  std::vector<std::size_t> frames;
  // Image folders: the folder's listing once it has been made (list_input_images returns it instead of listing
  // the folder again; a run lists its folder once, not at every step that needs the files).
  std::shared_ptr<const ImageListing> listing;
};

// The kind `automatic` stands for: a folder holds images, unless it is a ROS 2 bag folder (metadata.yaml
// and a .db3 or .mcap file); a .bag, .db3 or .mcap file is a bag; a .npy file whose name contains
// "similarity" is a similarity matrix, any other .npy holds descriptors; any other file is read as a video.
// Throws InputError naming the path when it does not exist.
InputKind resolve_input_kind(const SequenceInput& input);

// Natural order of file names, glibc's strverscmp (as `ls -v` sorts): runs of digits compare by value
// ("2.jpg" < "10.jpg", "run_9" < "run_10"), other bytes in byte order ("B.png" < "a.png"); a run with leading
// zeros sorts before one without ("07" < "7"). A total order: only equal names compare equal.
bool natural_less(std::string_view a, std::string_view b);

// The image files of a folder (by extension: png, jpg, jpeg, bmp, tif, tiff, webp, pgm, ppm, pnm, jp2),
// in natural order. Hidden files and files whose name starts with "ground_truth" are skipped: a
// ground-truth matrix often sits beside the images and is not part of the sequence. An entry with an image
// extension that is not a readable regular file (a dangling or looping symbolic link, a folder, a FIFO or
// a socket) is an InputError naming it. Throws InputError naming the folder when it cannot be read or holds
// no image.
std::vector<std::filesystem::path> list_images(const std::filesystem::path& folder);

struct ListOptions {
  // Walk the subfolders too (hidden ones skipped, symbolic links to folders not followed). The order is
  // the natural order of the relative paths, compared folder name by folder name: a/2.png, a/10.png,
  // b/1.png, b.png (a depth-first walk with each folder's entries in natural order).
  bool recursive = false;
  // Leave out, instead of refusing, entries that cannot be read: not regular files, and (decoded once
  // here) corrupt images. They are listed in ImageListing::skipped.
  bool skip_unreadable = false;
};

struct ImageListing {
  std::vector<std::filesystem::path> files;
  std::vector<std::pair<std::filesystem::path, std::string>> skipped;  // entry, why
};

ImageListing list_images(const std::filesystem::path& folder, const ListOptions& options);

// The listing of an image-folder input with its options (recursive, skip_unreadable), every input.every-th
// image: input.listing when set (made by this function, so already thinned).
ImageListing list_input_images(const SequenceInput& input);

// How many of n frames --every keeps (every >= 1): 0, every, 2 * every, ... below n.
inline std::size_t every_kth_count(std::size_t n, std::size_t every) { return (n + every - 1) / every; }

// Elements 0, every, 2 * every, ... of `all` (every >= 1): the frames --every keeps.
template <typename T>
std::vector<T> every_kth(const std::vector<T>& all, std::size_t every) {
  std::vector<T> out;
  for (std::size_t k = 0; k < all.size(); k += every) out.push_back(all[k]);
  return out;
}

// The rows of a descriptors.npy input, every input.every-th (InputError naming the file when unreadable).
DenseMatrix<float> read_input_rows(const SequenceInput& input);

// A similarity.npy input: InputError naming --every when it asks for every K-th frame (a matrix is not thinned).
void refuse_every_for_similarity(const SequenceInput& input);

// A frame's name for the report: the file name, or the path relative to the folder when recursive.
std::string image_name(const std::filesystem::path& folder, const std::filesystem::path& file, bool recursive);

}  // namespace seqtopo::pipeline
