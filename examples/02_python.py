#!/usr/bin/env python3
"""Lesson 2: loop closures from Python, on a folder of images (or a video, or a camera).

Steps as in lesson 1: options, a Detector with a new map file, one process() call per image in
acquisition order, each Result read, the map closed (the `with` block).

Usage: PYTHONPATH=build/python python3 examples/02_python.py IMAGES_DIR|VIDEO|CAMERA_NUMBER MAP.db
(`memloop generate route` writes a folder of images to try it on: route/images.)
"""
import os
import re
import sys

import cv2

import memloop


def frames(source):
    """Images in acquisition order: a folder in natural order, else a video file or a camera."""
    if os.path.isdir(source):
        natural = lambda name: [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", name)]
        for name in sorted(os.listdir(source), key=natural):
            yield cv2.imread(os.path.join(source, name))
        return
    capture = cv2.VideoCapture(int(source) if source.isdigit() else source)
    while True:
        ok, image = capture.read()
        if not ok:
            return
        yield image


def main(source, map_file):
    # The default parameters; the time limit off so the run repeats exactly.
    options = memloop.Options({"memory.time_limit_ms": 0})
    with memloop.Detector(options, map_file) as detector:
        for index, image in enumerate(frames(source)):
            result = detector.process(image, index)
            if result.has_loop_closure:
                print(f"image {index}: loop closure with image {result.loop_closure_images[0]} "
                      f"(location {result.loop_closure_id}, p={result.hypothesis_value:.2f})")
    print(f"{index + 1} images, map in {map_file}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    try:
        main(sys.argv[1], sys.argv[2])
    except memloop.Error as error:  # the message names the input and the problem
        sys.exit(f"error: {error}")
