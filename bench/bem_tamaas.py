"""The same contact problem solved by tamaas (run with a Python that has tamaas installed, in
a throwaway environment; tamaas is not a dependency of fastline).

    python3 -m venv /tmp/venv-tamaas   # then install tamaas there with its pip
    /work/venv/bin/python -m bench.bem_scaling --save 1024 4      # writes the problem .npz
    /tmp/venv-tamaas/bin/python bench/bem_tamaas.py /tmp/bem_problem_1024_4.npz

Prints tamaas' CPU time, contact fraction and mean gap on the problem saved by
``bench.bem_scaling --save N K`` (the surface of that module, nominal pressure number K), at
the tolerance 1e-8 of its Polonsky-Keer-Rey solver (tamaas' own stopping rule).
"""

import sys
import time

import numpy as np
import tamaas as tm

data = np.load(sys.argv[1])
g0 = data["g0"]
n = g0.shape[0]
length = float(data["L"])
model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [length, length], [n, n])
model.E = float(data["E_star"])
model.nu = 0.0  # E / (1 - nu^2) = E*
surface = np.ascontiguousarray(-g0)  # tamaas: a rigid surface of these heights
solver = tm.PolonskyKeerRey(model, surface, 1e-8)
solver.max_iter = 100000
t0 = time.process_time()
solver.solve(float(data["pressure"]))
dt = time.process_time() - t0
p = np.asarray(model.traction).reshape(n, n)
gap = np.asarray(model.displacement).reshape(n, n) - surface
gap -= gap[p > 0].mean()
print(
    f"tamaas {tm.__version__}: N = {n}, CPU {dt:.2f} s, A/A0 = {np.mean(p > 0):.4f}, "
    f"mean gap {gap.clip(0).mean():.4e} m, mean p {p.mean():.4e} Pa"
)
