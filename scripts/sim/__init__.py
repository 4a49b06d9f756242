"""Reference vehicle simulator: stands in for the paper's CarSim (MODEL.md, DATA.md).

Modules: vehicle (parameters, 7-DOF two-track dynamics, RK4), tyres (truth tyre models
"dugoff" and "mf"), control (closed-loop inputs: per-wheel ABS, driver yaw controller),
scenarios (MODEL.md section 8 inputs and the ABS hard-braking set), sensors (sensor noise,
truth utilisation, CSV logs), observer_scenarios (issue 16: scenarios that break velocity and
sideslip observers -- ABS braking on low / high / split mu, traction-limited RWD / AWD
acceleration, sine with dwell and double lane change on high and low mu, a steady circle,
banked curves +-5 deg, an ay bias, a 600 s straight, creep and stop, a hill with known grade;
the list with each one's purpose is its docstring), mass_grade_scenarios (issue 19: straight
drives on graded roads with rolling resistance, drag, wind, brake stops and gear-shift torque
gaps, for the mass and grade estimator).  The observer scenarios use the options
of vehicle.py (road grade and bank, low-speed slip floor) and control.py (drive layouts,
traction control, cruise and path control) that the friction scenarios leave off.
CLI: scripts/data/make_scenarios.py, scripts/data/make_observer_scenarios.py,
scripts/data/make_mass_grade_scenarios.py.
Tests: scripts/sim/test_sim.py, scripts/sim/test_observer.py.
"""
