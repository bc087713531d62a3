#pragma once
// The exponentials of the two-layer closure's rows, by glibc's vector exp
// (exponentials.cpp, the one file built with -ffast-math). A header of its
// own so that that file includes nothing with inline code: an inline
// function compiled there under -ffast-math could be the copy the linker
// keeps for every other file.

namespace coflow::fluid::fv {

// a[i] = exp(a[i]) for i < n: within a few ulps of std::exp, not the same bits.
void exp_in_place(double* a, long n);

}  // namespace coflow::fluid::fv
