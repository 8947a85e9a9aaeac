"""gyrosid from Python: simulate a gyro, calibrate, compensate, analyse noise, score by the criterion of fit,
explain a mismatch, design a calibration trajectory, run an adaptive session, or learn and screen a production lot - in-process, numpy arrays in and out. Models save to and load from the same JSON files as
the `gyrosid` command, so the two can be mixed freely.

    import gyrosid
    rec = gyrosid.simulate(trajectory="builtin:trajectories/dual_scan.yaml", seed=1)
    model = gyrosid.calibrate(rec, model="rbf", solver="ols", options={"width": 0.3})
    print(gyrosid.cof(model, trajectory="short")["end_error_m"])
"""
from ._gyrosid import (Error, Model, Recording, allan, calibrate, calibrate_triad, cof, compensate, design,  # noqa: F401
                       explain, load_model, lot_learn, lot_screen, run_main_job, session, simulate, surface)

__all__ = ["Error", "Model", "Recording", "allan", "calibrate", "calibrate_triad", "cof", "compensate", "design",
           "explain", "load_model", "lot_learn", "lot_screen", "run_main_job", "session", "simulate", "surface"]
