#!/bin/sh
# /init of the virtual board's initramfs (scripts/virtual-board.sh): mounts the kernel file
# systems, loads the drivers, mounts the host's run directory over 9p and runs the guest.sh
# found there. Lines starting with "LUMAR-VB: " on the serial console are for the host.
# Powers off at the end whatever happens, so QEMU exits.
export PATH=/usr/bin:/usr/sbin HOME=/root
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
mkdir -p /dev/shm /dev/pts
mount -t tmpfs tmpfs /dev/shm
mount -t tmpfs tmpfs /tmp
mount -t tmpfs tmpfs /run
exec </dev/console >/dev/console 2>&1
echo "LUMAR-VB: userspace uptime $(cut -d' ' -f1 /proc/uptime) s"

display=bochs
for arg in $(cat /proc/cmdline); do
  case "$arg" in lumar.display=*) display=${arg#lumar.display=} ;; esac
done

status=1
if modprobe virtio_pci && modprobe 9pnet_virtio && modprobe 9p &&
   mount -t 9p -o trans=virtio,version=9p2000.L,msize=1048576 host /mnt/host; then
  # vivid's first capture node becomes /dev/video0 (nothing else registers video nodes).
  modprobe vivid || echo "LUMAR-VB: modprobe vivid failed"
  case "$display" in
    virtio) modprobe virtio-gpu || echo "LUMAR-VB: modprobe virtio-gpu failed" ;;
    *) modprobe bochs || echo "LUMAR-VB: modprobe bochs failed" ;;
  esac
  # devtmpfs creates the nodes as the drivers register them; give them a moment.
  for _ in $(seq 50); do
    [ -e /dev/video0 ] && [ -e /dev/dri/card0 ] && break
    sleep 0.1
  done
  echo "LUMAR-VB: modules loaded, uptime $(cut -d' ' -f1 /proc/uptime) s"
  # llvmpipe's compiled shaders from earlier runs (the host keeps them between runs).
  export MESA_SHADER_CACHE_DIR=/tmp/mesa-shader-cache
  [ -d /mnt/host/mesa-shader-cache ] && cp -a /mnt/host/mesa-shader-cache "$MESA_SHADER_CACHE_DIR"
  cd /mnt/host && sh ./guest.sh
  status=$?
  cd /
  if [ -d "$MESA_SHADER_CACHE_DIR" ]; then
    rm -rf /mnt/host/mesa-shader-cache
    cp -a "$MESA_SHADER_CACHE_DIR" /mnt/host/mesa-shader-cache
  fi
else
  echo "LUMAR-VB: cannot mount the host's run directory over 9p"
fi
echo "LUMAR-VB: done status $status uptime $(cut -d' ' -f1 /proc/uptime) s"
sync
umount /mnt/host 2>/dev/null
poweroff -f
