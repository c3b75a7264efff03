"""Data in and out: the readers (:mod:`~footnav.data.io`), the simulator
(:mod:`~footnav.data.simulate`), the registry of shared recordings (:mod:`~footnav.data.datasets`)
and the result files (:mod:`~footnav.data.results`, :mod:`~footnav.data.output`); the bundled demo
recording lies in ``azure_fgo/``.
"""
