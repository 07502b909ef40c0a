#!/usr/bin/env python3
"""The peers of `driftlab convert` in BENCHMARKS.md ("Drone and robot logs"): the same
topics read from the same file by pyulog 1.3.0 and pymavlink 2.4.50, the way the data
README's reference CSVs were made.

    python3 bench/drone_peers.py ulog FILE.ulg   # sensor_gyro, sensor_accel, sensor_combined, vehicle_imu_status
    python3 bench/drone_peers.py dataflash FILE.bin   # every IMU message
"""
import sys


def ulog(path):
    from pyulog import ULog
    topics = ['sensor_gyro', 'sensor_accel', 'sensor_combined', 'vehicle_imu_status']
    u = ULog(path, topics)
    n = sum(len(d.data['timestamp']) for d in u.data_list)
    print(f'{n} samples of {len(u.data_list)} subscriptions')


def dataflash(path):
    from pymavlink import mavutil
    m = mavutil.mavlink_connection(path)
    rows = []
    while True:
        msg = m.recv_match(type=['IMU', 'TCLR'])
        if msg is None:
            break
        rows.append((msg.TimeUS, msg.I, msg.GyrX, msg.GyrY, msg.GyrZ, msg.AccX, msg.AccY,
                     msg.AccZ, msg.T))
    print(f'{len(rows)} IMU messages')


if __name__ == '__main__':
    {'ulog': ulog, 'dataflash': dataflash}[sys.argv[1]](sys.argv[2])
