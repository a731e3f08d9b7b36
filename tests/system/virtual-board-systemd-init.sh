#!/bin/sh
# /init of the systemd virtual board's initramfs (scripts/virtual-board-systemd.sh): Debian's
# kernel has virtio_blk and ext4 as modules, so this busybox loads them, mounts the Debian root
# file system from the virtio disk and hands over to its systemd.
export PATH=/usr/bin:/usr/sbin
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
exec </dev/console >/dev/console 2>&1
echo "LUMAR-VBS: initramfs uptime $(cut -d' ' -f1 /proc/uptime) s"
# ext4 checksums its metadata with crc32c through the crypto API: load a driver for it too.
for m in virtio_pci virtio_blk crc32c_generic ext4; do
  modprobe "$m" || echo "LUMAR-VBS: modprobe $m failed"
done
for _ in $(seq 100); do
  [ -b /dev/vda ] && break
  sleep 0.1
done
mkdir -p /newroot
if ! mount -t ext4 -o rw,noatime /dev/vda /newroot; then
  echo "LUMAR-VBS: cannot mount the root file system /dev/vda"
  poweroff -f
fi
umount /sys /proc
mount --move /dev /newroot/dev 2>/dev/null || umount /dev
echo "LUMAR-VBS: switching to systemd"
exec switch_root /newroot /sbin/init
