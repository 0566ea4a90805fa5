#!/bin/sh
# Baseline (74a928c, session start) against HEAD on issue 27's 3:1 pair, default scene, alternating.
d=cpu:threads=1:cores=0,cpu:threads=1:cores=1:speed=0.3333
b=uniform,static,queue,semi-static,dlb,hybrid
sleep 45
for k in 1 2; do
  echo "== base $k $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)"
  /tmp/multiray_baseline bench --res 640x360 --spp 2 --frames 100 --devices $d --balancers $b --repeats 3 --json /tmp/b28/base-$k.json > /tmp/b28/base-$k.txt 2>&1
  echo "== head $k $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)"
  /work/main/build/src/app/multiray bench --res 640x360 --spp 2 --frames 100 --devices $d --balancers $b --repeats 3 --json /tmp/b28/head-$k.json > /tmp/b28/head-$k.txt 2>&1
done
echo "== done $(date -u +%T)"
