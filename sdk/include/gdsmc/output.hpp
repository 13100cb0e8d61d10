// gdsmc SDK: how plugins write results. The host owns the HDF5 file; a diagnostic writes into its
// own group through this sink and never links HDF5.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "gdsmc/version.hpp"

namespace gdsmc {

class GDSMC_API OutputSink {
 public:
  virtual ~OutputSink() = default;

  // Declare a time-series column (call from Diagnostic::begin). At each record the host writes
  // the time (tau0) and s beside the columns; the diagnostic appends exactly one value to each of
  // its columns per record.
  virtual std::size_t series(const std::string& name, const std::string& unit, const std::string& doc) = 0;
  virtual void append(std::size_t series_id, double value) = 0;

  // Declare a profile series (call from Diagnostic::begin): at each record the diagnostic appends
  // one value per sampling bin along y (SystemInfo::bins); the host writes a (record x bin)
  // dataset with the bin centres and, like series, realization averages and steady means.
  virtual std::size_t profile(const std::string& name, const std::string& unit, const std::string& doc) = 0;
  // Append one record of a profile: SystemInfo::bins values.
  virtual void append_profile(std::size_t profile_id, const double* values) = 0;

  // A whole array (a matrix, a final profile) with its shape, row-major.
  virtual void array(const std::string& name, const std::vector<double>& data,
                     const std::vector<std::size_t>& shape, const std::string& unit, const std::string& doc) = 0;
  // A histogram: bin edges (size = values.size() + 1) and values.
  virtual void histogram(const std::string& name, const std::vector<double>& edges,
                         const std::vector<double>& values, const std::string& edge_unit,
                         const std::string& value_unit, const std::string& doc) = 0;
  virtual void scalar(const std::string& name, double value, const std::string& unit, const std::string& doc) = 0;
  // A text attribute on the diagnostic's group.
  virtual void attribute(const std::string& name, const std::string& value) = 0;
  // A line for the end-of-run summary printed by `gdsmc run`.
  virtual void summary(const std::string& line) = 0;

  // SDK 6.3 (appended: a minor version). Marks `dataset` (a series, profile, array, histogram or
  // scalar this diagnostic already declared or wrote) as theory for the measured `measured` of the
  // same group (a name, several separated by commas, or "" when there is no measured twin), citing
  // `equation` ("002 Eq. 27"). Call it once per theory dataset, after it and its measured twins
  // exist. The host writes the attributes role = "theory", theory_of and equation on the dataset;
  // `gdsmc plot` and the report scripts pair theory with measurement by them alone.
  virtual void theory(const std::string& dataset, const std::string& measured, const std::string& equation) = 0;

  // SDK 6.4 (appended: a minor version). Declares that the 1-D array `dataset` holds its values at
  // the points of the 1-D array `grid` of the same group, of the same length (a steady profile over
  // its bin centres, a theory curve over its alpha grid). Call it once per dataset, after both are
  // written. The host writes the attribute axis = grid on the dataset; `gdsmc plot` draws the
  // dataset against its grid (against its index when it declares none).
  virtual void axis(const std::string& dataset, const std::string& grid) = 0;
};

}  // namespace gdsmc
