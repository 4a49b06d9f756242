"""Reference vehicle simulator: stands in for the paper's CarSim (MODEL.md, DATA.md).

Modules: vehicle (parameters, 7-DOF two-track dynamics, RK4), tyres (truth tyre models
"dugoff" and "mf"), scenarios (MODEL.md section 8 inputs), sensors (sensor noise, CSV logs).
CLI: scripts/make_scenarios.py.  Tests: scripts/sim/test_sim.py.
"""
