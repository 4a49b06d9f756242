"""Reference vehicle simulator: stands in for the paper's CarSim (MODEL.md, DATA.md).

Modules: vehicle (parameters, 7-DOF two-track dynamics, RK4), tyres (truth tyre models
"dugoff" and "mf"), control (closed-loop inputs: per-wheel ABS, driver yaw controller),
scenarios (MODEL.md section 8 inputs and the ABS hard-braking set), sensors (sensor noise,
truth utilisation, CSV logs).
CLI: scripts/data/make_scenarios.py.  Tests: scripts/sim/test_sim.py.
"""
