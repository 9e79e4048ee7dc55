#!/usr/bin/python3
"""Publishes a folder's images on a topic at a camera's rate, as a robot's driver would, and
reports what memloop_node made of them: images processed and dropped, iteration time, and the
latency from an image's publication to its loop closure message (bench/ros_live.sh runs it).

Usage: ros_publish.py IMAGES_DIR RATE_HZ [TOPIC]"""
import os
import re
import sys
import threading
import time

import cv2
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from memloop_msgs.msg import LoopClosure
from sensor_msgs.msg import Image


def natural(name):
    return [int(part) if part.isdigit() else part for part in re.split(r"(\d+)", name)]


def main():
    folder, rate = sys.argv[1], float(sys.argv[2])
    topic = sys.argv[3] if len(sys.argv) > 3 else "/camera/image_raw"
    names = sorted(os.listdir(folder), key=natural)
    rospy.init_node("ros_publish", anonymous=True)
    published = {}  # header stamp -> wall time of publication
    latencies = []
    status = {}
    lock = threading.Lock()

    def on_loop(loop):
        now = time.monotonic()
        with lock:
            sent = published.get(loop.query_stamp.to_nsec())
            if sent is not None:
                latencies.append(1000 * (now - sent))

    def on_diagnostics(array):
        for entry in array.status:
            if entry.name == "memloop: loop closure detection":
                with lock:
                    status.update({pair.key: pair.value for pair in entry.values})

    rospy.Subscriber("/memloop/loop_closures", LoopClosure, on_loop, queue_size=1000)
    rospy.Subscriber("/diagnostics", DiagnosticArray, on_diagnostics)
    publisher = rospy.Publisher(topic, Image, queue_size=1000)
    while publisher.get_num_connections() == 0 and not rospy.is_shutdown():
        time.sleep(0.05)
    time.sleep(1.0)  # the loop-closure subscription connects too
    images = [cv2.imread(os.path.join(folder, name)) for name in names]
    period = 1.0 / rate
    start = time.monotonic()
    for index, bgr in enumerate(images):
        time.sleep(max(0.0, start + index * period - time.monotonic()))
        message = Image()
        message.header.stamp = rospy.Time.from_sec(1000 + index * period)
        message.header.frame_id = "camera"
        message.height, message.width = bgr.shape[:2]
        message.encoding = "bgr8"
        message.step = 3 * message.width
        message.data = bgr.tobytes()
        with lock:
            published[message.header.stamp.to_nsec()] = time.monotonic()
        publisher.publish(message)
    # Until the node has taken every image and has none waiting.
    while not rospy.is_shutdown():
        with lock:
            done = (int(status.get("images received", -1)) == len(images) and
                    int(status.get("images waiting", -1)) == 0)
        if done:
            break
        time.sleep(0.2)
    time.sleep(1.5)  # one more diagnostics message, the last loop closures
    latencies.sort()
    median = latencies[len(latencies) // 2] if latencies else float("nan")
    print(f"images published: {len(images)} at {rate:g} Hz; "
          f"received {status['images received']}, processed {status['images processed']}, "
          f"dropped {status['images dropped']}, skipped {status['images skipped']}; "
          f"loop closures {status['loop closures']}; "
          f"iteration median {status['iteration time median (ms)']} ms "
          f"(of the last 100), max {status['iteration time max (ms)']} ms; "
          f"latency image -> loop closure message: median {median:.1f} ms, "
          f"max {max(latencies) if latencies else float('nan'):.1f} ms "
          f"({len(latencies)} messages); node's own latency median "
          f"{status['latency median (ms)']} ms, max {status['latency max (ms)']} ms")


if __name__ == "__main__":
    main()
