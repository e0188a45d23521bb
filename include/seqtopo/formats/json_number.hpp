#pragma once
// A float as the JSON files write it: the double of its shortest decimal, so that a JSON library prints 0.85 and
// not 0.8500000238418579 (the float's exact value), and reading it back as a float gives the same float.
namespace seqtopo::formats {

double json_number(float value);

}  // namespace seqtopo::formats
