from concurrent.futures import ThreadPoolExecutor

import camdyn

scene = camdyn.load("studies/quickstart.json", set={"cam.rpm": 1200})
result = scene.simulate()  # camdyn.InputError / camdyn.SolverError on failure
print(f"jump speed {camdyn.jump_speed(scene):.0f} rpm, "
      f"peak contact force {result.metrics['peak_contact_force']:.0f} N, "
      f"{result.metrics['impact_count']:.0f} impacts")
ts = result.timeseries  # time [s], cam_angle_deg [deg], gap [m], contact_force [N], ...
print(f"largest gap {ts['gap'].max() * 1e3:.3f} mm")

# The GIL is released while camdyn computes: threads sweep in parallel.
speeds = [900, 1100, 1300, 1500]
scenes = [camdyn.load("studies/quickstart.json", set={"cam.rpm": rpm}) for rpm in speeds]
with ThreadPoolExecutor() as pool:
    runs = list(pool.map(lambda s: s.simulate(series=False), scenes))

for rpm, run in zip(speeds, runs):
    print(f"{rpm} rpm: separated {100 * run.metrics['separation_fraction']:.1f} % of the time")
