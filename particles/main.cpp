#include "coflow/catalog.hpp"
#include "coflow/session.hpp"
#include "particles/driver.hpp"

int main(int argc, char** argv) {
  return coflow::coupler::run_component("particles", argc, argv, coflow::catalog(), coflow::particles::run);
}
