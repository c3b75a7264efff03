"""Analysis of results: metrics against a reference, evaluation reports, batch runs, detector
comparisons and figures (:mod:`~footnav.analysis.plot`, needs matplotlib)."""
