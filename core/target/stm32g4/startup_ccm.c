/* Example start-up for stm32g474_ccm.ld: FPU on, the code linked for CCM
 * SRAM (.ramfunc) and .data copied from flash, .bss zeroed, then main. No
 * clock, flash latency or peripheral set-up: those are the firmware's. */
#include <stdint.h>

extern uint32_t __stack_top, __bss_start__, __bss_end__;
extern uint32_t __ramfunc_start__, __ramfunc_end__, __ramfunc_load__;
extern uint32_t __data_start__, __data_end__, __data_load__;
int main(void);

static void copy(uint32_t *dst, uint32_t *end, const uint32_t *src)
{
    while (dst < end) *dst++ = *src++;
}

void Reset_Handler(void)
{
    uint32_t *p;
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20; /* CPACR: CP10, CP11 (the FPU) */
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    copy(&__ramfunc_start__, &__ramfunc_end__, &__ramfunc_load__);
    copy(&__data_start__, &__data_end__, &__data_load__);
    for (p = &__bss_start__; p < &__bss_end__; p++) *p = 0;
    __asm__ volatile("isb" ::: "memory"); /* fetch the copied code afresh */
    (void)main();
    for (;;) {
    }
}

static void Default_Handler(void)
{
    for (;;) {
    }
}

__attribute__((section(".vectors"), used)) static void (*const vectors[16])(void) = {
    (void (*)(void))(&__stack_top), Reset_Handler, Default_Handler, Default_Handler,
    Default_Handler, Default_Handler, Default_Handler, 0, 0, 0, 0, Default_Handler,
    Default_Handler, 0, Default_Handler, Default_Handler};
