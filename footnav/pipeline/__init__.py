"""The pipeline: the factory that composes components by name (:mod:`~footnav.pipeline.factory`),
the clock-sync stage (:mod:`~footnav.pipeline.sync`), the online session
(:mod:`~footnav.pipeline.online`) and the run's result (:mod:`~footnav.pipeline.result`).

Imports the components (detectors, estimators, fusion), the plugins and the layers below them.
"""
