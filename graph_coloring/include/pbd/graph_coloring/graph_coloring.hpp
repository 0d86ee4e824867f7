#pragma once
/// \file graph_coloring.hpp
/// Everything of pbd::graph_coloring: groups items (constraints) into colors, batches in which no two
/// items share a non-fixed node (particle), so each batch can be processed in parallel; and splits the nodes into
/// blocks of about equal item count cutting few items (partition(), METIS).
#include "pbd/graph_coloring/color.hpp"
#include "pbd/graph_coloring/coloring.hpp"
#include "pbd/graph_coloring/error.hpp"
#include "pbd/graph_coloring/hypergraph.hpp"
#include "pbd/graph_coloring/partition.hpp"
#include "pbd/graph_coloring/stats.hpp"
#include "pbd/graph_coloring/validate.hpp"
