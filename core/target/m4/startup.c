/* Bare-metal start of the vector runner on QEMU's mps2-an386 (Cortex-M4F):
 * vector table, FPU on, .bss zeroed, main, exit through semihosting. */
#include <stdint.h>

extern uint32_t __stack_top, __bss_start__, __bss_end__;
int main(void);
void smd_exit(int code);

void Reset_Handler(void)
{
    uint32_t *p;
    /* CPACR: full access to CP10 and CP11 (the FPU) */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    for (p = &__bss_start__; p < &__bss_end__; p++) *p = 0;
    smd_exit(main());
}

static void Fault_Handler(void) { smd_exit(99); }

__attribute__((section(".vectors"), used)) static void (*const vectors[16])(void) = {
    (void (*)(void))(&__stack_top), Reset_Handler, Fault_Handler, Fault_Handler,
    Fault_Handler, Fault_Handler, Fault_Handler, 0, 0, 0, 0, Fault_Handler, Fault_Handler,
    0, Fault_Handler, Fault_Handler};
