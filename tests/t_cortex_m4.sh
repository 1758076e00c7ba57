#!/bin/sh
# core/ compiles and links freestanding for a Cortex-M4 (arm-none-eabi-gcc -mcpu=cortex-m4
# -mthumb -Os) into boards/cortex-m4's image with a static arena; prints the .text size of
# the core and the image's flash and RAM use.
set -eu
B=${BUILD:-build}
command -v arm-none-eabi-gcc >/dev/null || { echo "arm-none-eabi-gcc missing (make deps)"; exit 1; }
O="$B/m4"; mkdir -p "$O"
CF="-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -Os -ffreestanding -std=c99 -pedantic
    -Wall -Wextra -Werror -Wmissing-prototypes -Wshadow -ffp-contract=off -fno-math-errno
    -ffunction-sections -fdata-sections -Icore"
objs=""
for c in core/*.c; do
  o="$O/$(basename "$c" .c).o"
  arm-none-eabi-gcc $CF -c "$c" -o "$o"
  objs="$objs $o"
done
arm-none-eabi-gcc $(echo $CF | sed "s/-pedantic//") -c boards/cortex-m4/firmware.c -o "$O/firmware.o"
arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -nostartfiles \
  --specs=nano.specs -Wl,--gc-sections -T boards/cortex-m4/link.ld \
  -o "$O/voroprobe-m4.elf" "$O/firmware.o" $objs -lm
text=$(arm-none-eabi-size -t $objs | awk 'END {print $1}')
set -- $(arm-none-eabi-size "$O/voroprobe-m4.elf" | awk 'NR==2 {print $1, $2, $3}')
echo "cortex-m4: core .text $text bytes ($(echo $objs | wc -w) objects); image flash $(( $1 + $2 )) bytes, RAM $(( $2 + $3 )) bytes (static arena included)"
