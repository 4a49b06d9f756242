"""Independent float64 reference estimator (the "yardstick") for road-friction estimation.

This package implements shared/docs/MODEL.md sections 3-6 (kinematics, slips, loads,
Dugoff tyre in paper and absolute mode, observation matrix H, SCKF and the paper's CKF)
independently of the C library, and writes the golden estimate logs the C tests compare
against.  It shares no code with the C library on purpose.

Modules
-------
params    parameter defaults, parameter files and sensor-log metadata (DATA.md)
model     MODEL.md sections 3-5 (vectorised over samples with numpy)
filters   MODEL.md section 6: SCKF (numpy.linalg.qr) and CKF (numpy.linalg.cholesky)
logs      sensor-log reader and estimate-log writer (DATA.md)
log_units a recorded log's column names, units, scales and offsets to SI (DATA.md; standard
          library only: the plotting tools read car logs with it too)
estimate  command line: run one filter on one sensor log

Small matrices never use threads, but BLAS thread counts are pinned to one anyway so the
golden files are byte-for-byte reproducible (only takes effect if numpy is not imported yet).
"""

import os as _os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    _os.environ.setdefault(_var, "1")
