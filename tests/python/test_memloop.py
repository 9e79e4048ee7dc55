"""The Python module, as a user imports it (run by ctest: PYTHONPATH=build/python)."""
import csv
import os
import subprocess
import threading

import cv2
import numpy as np
import pytest

import memloop

CLI = os.environ.get("MEMLOOP_CLI", "memloop")
NO_TIME_LIMIT = {"memory.time_limit_ms": 0, "memory.max_wm_locations": 30}


@pytest.fixture(scope="module")
def route(tmp_path_factory):
    """The built-in generated route, written by the CLI, and the CLI's own run on it."""
    folder = tmp_path_factory.mktemp("route")
    subprocess.run([CLI, "generate", str(folder)], check=True, capture_output=True)
    images = folder / "images"
    names = sorted(os.listdir(images), key=lambda name: int(name.split(".")[0]))
    out = folder / "cli.csv"
    settings = [f"{name}={value}" for name, value in NO_TIME_LIMIT.items()]
    subprocess.run([CLI, "run", str(images), "--out", str(out), "--set", *settings], check=True,
                   capture_output=True)
    with open(out, newline="") as rows:
        cli_loops = [(int(row["image"]), int(row["matched_image"]))
                     for row in csv.DictReader(rows) if row["matched_image"]]
    return [str(images / name) for name in names], cli_loops


def test_parameters_list_the_registry():
    rows = {row["name"]: row for row in memloop.parameters()}
    assert rows["memory.stm_size"]["type"] == "int"
    assert rows["surf.upright"]["type"] == "bool"
    assert isinstance(rows["surf.upright"]["default"], bool)
    assert rows["filter.loop_threshold"]["range"] == "[0, 1]"


def test_options_through_the_registry():
    options = memloop.Options({"memory.stm_size": 12, "surf.upright": False})
    assert options["memory.stm_size"] == 12
    assert options["surf.upright"] is False
    options["dictionary.seed"] = 1234567
    assert options["dictionary.seed"] == 1234567
    assert memloop.Options(preset="paper2011")["filter.hypothesis_value"] == "best_neighbours"
    with pytest.raises(memloop.ParameterError, match="Unknown parameter 'memory.stm'"):
        options["memory.stm"] = 3
    with pytest.raises(memloop.ParameterError, match=r"must be in \[0, 1\]"):
        memloop.Options({"filter.loop_threshold": 7})


def test_same_loop_closures_as_the_cli(route, tmp_path):
    paths, cli_loops = route
    assert len(cli_loops) > 20
    loops = []
    with memloop.Detector(memloop.Options(NO_TIME_LIMIT), str(tmp_path / "map.db")) as detector:
        for index, path in enumerate(paths):
            image = cv2.imread(path)  # BGR, as a user's program reads it
            result = detector.process(image, index)
            assert result.image_index == index
            if result.has_loop_closure:
                loops.append((index, result.loop_closure_images[0]))
    assert loops == cli_loops
    assert memloop.read_map_options(str(tmp_path / "map.db"))["memory.max_wm_locations"] == 30


def test_localization_leaves_the_map_unchanged(route, tmp_path):
    paths, _ = route
    lap_one, lap_two = range(0, 110), range(110, 190)  # lap 1 and its detour; lap 2
    map_path = tmp_path / "lap1.db"
    with memloop.Detector(memloop.Options(NO_TIME_LIMIT), str(map_path)) as detector:
        for index in lap_one:
            detector.process(cv2.imread(paths[index]), index)
    before = map_path.read_bytes()
    options = memloop.read_map_options(str(map_path))
    options["memory.localization"] = True
    localized = []
    with memloop.Detector(options, str(map_path)) as detector:
        for index in lap_two:
            result = detector.process(cv2.imread(paths[index]), index)
            assert result.location_id == 0  # the image joins no location
            if result.has_loop_closure:
                localized.append(result.loop_closure_images)
    assert len(localized) >= 60  # of 80
    assert map_path.read_bytes() == before


def test_a_second_session_with_names_and_time_stamps(route, tmp_path):
    paths, _ = route
    map_path = str(tmp_path / "sessions.db")
    with memloop.Detector(memloop.Options(NO_TIME_LIMIT), map_path) as detector:
        for index in range(0, 110):  # lap 1 and its detour
            detector.process(cv2.imread(paths[index]), index, name=os.path.basename(paths[index]),
                             timestamp=100 + 0.5 * index)
    options = memloop.read_map_options(map_path)
    options["camera.fx"], options["camera.fy"] = 300.0, 300.0
    options["camera.cx"], options["camera.cy"] = 160.0, 120.0
    across = 0
    posed = 0
    with memloop.Detector(options, map_path, new_session=True) as detector:
        assert detector.session == 1 and detector.session_first_image == 110
        for index in range(110, 190):  # lap 2
            result = detector.process(cv2.imread(paths[index]), index, name=f"{index + 1}.png")
            assert result.session == 1 and result.timestamp is None
            across += result.has_loop_closure and result.loop_closure_images[0] < 110
            geometry = result.loop_closure_geometry
            if geometry.has_pose:
                posed += 1
                norm = sum(t * t for t in geometry.translation)
                assert abs(norm - 1) < 1e-6 if geometry.translation_known else norm == 0
                assert len(geometry.inliers) >= geometry.pose_inliers
                # The image whose keypoints the location holds: this one, or one Rehearsal merged.
                assert 110 <= geometry.query_view <= index
    assert across >= 40  # of 80
    assert posed > 0
    images = memloop.read_map_images(map_path)
    assert len(images) == 190
    assert images[3] == {"index": 3, "session": 0, "name": "4.png", "timestamp": 101.5}
    assert images[150]["session"] == 1 and images[150]["timestamp"] is None
    with pytest.raises(memloop.Error, match="give one"):
        memloop.Detector(options, map_path, resume=True, new_session=True)


def test_depth_makes_translations_metric(route, tmp_path):
    """process(image, depth=...): the generated route is a flat world seen square on, 2 m away."""
    paths, _ = route
    options = memloop.Options(NO_TIME_LIMIT)
    options["camera.fx"], options["camera.fy"] = 300.0, 300.0
    options["camera.cx"], options["camera.cy"] = 160.0, 120.0
    metric = loops = 0
    with memloop.Detector(options, str(tmp_path / "rgbd.db")) as detector:
        for index, path in enumerate(paths[:190]):
            image = cv2.imread(path)
            depth = np.full(image.shape[:2], 2000, dtype=np.uint16)  # millimetres
            result = detector.process(image, index, depth=depth)
            if result.has_loop_closure:
                loops += 1
                geometry = result.loop_closure_geometry
                metric += geometry.has_pose and geometry.translation_metric
                assert result.loop_closure_images[0] == geometry.match_view
        assert loops > 20 and metric >= 0.9 * loops
        with pytest.raises(memloop.InputError, match="uint16 .millimetres. or float32"):
            detector.process(image, 190, depth=np.zeros(image.shape[:2], dtype=np.float64))
        with pytest.raises(memloop.InputError, match="the depth map is 16x8, the image 320x240"):
            detector.process(image, 190, depth=np.zeros((8, 16), dtype=np.float32))


def test_grey_images_and_results(tmp_path):
    image = np.random.default_rng(3).integers(0, 256, (240, 320), dtype=np.uint8)
    detector = memloop.Detector(memloop.Options(NO_TIME_LIMIT), str(tmp_path / "grey.db"))
    result = detector.process(cv2.GaussianBlur(image, (5, 5), 1.5), 0)
    assert result.location_id == 1 and not result.has_loop_closure
    assert result.feature_count > 0 and result.times.total_ms > 0
    # The detector's thread ran for part of the iteration's wall time, never longer.
    assert 0 < result.times.cpu_ms <= result.times.total_ms + 1
    assert 0 <= result.times.ltm_read_ms <= result.times.total_ms
    # Nothing in LTM yet: nothing retrieved, deferred or matched by appearance.
    assert result.retrieved_ids == [] and result.retrievals_deferred == 0
    assert result.retrievals_unread == 0
    assert result.appearance_match_id == 0 and result.appearance_match_z == 0
    assert result.time_decided == ""  # T_time off: time decides nothing
    assert "image 0 -> location 1" in repr(result)
    detector.close()
    with pytest.raises(memloop.Error, match="the detector is closed"):
        detector.process(image, 1)


def test_errors_carry_the_messages(tmp_path):
    path = tmp_path / "notes.db"
    path.write_text("my notes")
    with pytest.raises(memloop.DatabaseError, match="notes.db: not a memloop map"):
        memloop.Detector(memloop.Options(), str(path))
    assert path.read_text() == "my notes"
    with memloop.Detector(memloop.Options(NO_TIME_LIMIT), str(tmp_path / "x.db")) as detector:
        with pytest.raises(memloop.InputError, match="must be a uint8 numpy array"):
            detector.process(np.zeros((8, 8), dtype=np.float32), 0)
        with pytest.raises(memloop.InputError, match="H x W"):
            detector.process(np.zeros((8, 8, 4), dtype=np.uint8), 0)


def test_realtime_priority_on_the_calling_thread():
    with pytest.raises(memloop.Error, match="real-time priority 100 is out of range"):
        memloop.set_realtime_priority(100)
    seen = {}

    def on_its_own_thread():  # the pytest thread keeps its scheduling
        try:
            memloop.set_realtime_priority(4)
        except memloop.Error as error:
            seen["refused"] = str(error)
            return
        seen["priority"] = memloop.realtime_priority()

    thread = threading.Thread(target=on_its_own_thread)
    thread.start()
    thread.join()
    assert memloop.realtime_priority() == 0
    if "refused" in seen:
        assert "cannot run at real-time priority 4 (SCHED_FIFO)" in seen["refused"]
        pytest.skip("this machine refuses SCHED_FIFO: " + seen["refused"])
    assert seen["priority"] == 4


def test_example_script_runs(route, tmp_path):
    paths, cli_loops = route
    script = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "02_python.py")
    run = subprocess.run([os.sys.executable, script, os.path.dirname(paths[0]),
                          str(tmp_path / "example.db")], capture_output=True, text=True,
                         check=True)
    assert "loop closure with image" in run.stdout
    assert f"{len(paths)} images" in run.stdout
